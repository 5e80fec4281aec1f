#include "pllvo/features/lines/synth_line_sequence.h"

#include <cmath>
#include <string>

#include "pllvo/common/error.h"
#include "pllvo/io/dataset_files.h"
#include "pllvo/io/euroc_sequence.h"

namespace pllvo::lines {

namespace fs = std::filesystem;

bool SynthLineSequence::edge_point(size_t k, int id, const Eigen::Vector2d& uv, Eigen::Vector3d& X_world) const {
  const auto it = edges.find(id);
  Eigen::Vector3d bearing;
  if (it == edges.end() || !camera->unproject(uv, bearing)) return false;
  // Closest point of the edge's line to the ray c + s * r (both lines in the world frame).
  const Eigen::Vector3d c = T_world_cam[k].translation(), r = T_world_cam[k].linear() * bearing.normalized();
  const Eigen::Vector3d a = it->second.a, e = (it->second.b - it->second.a).normalized();
  const double b = e.dot(r), denom = 1.0 - b * b;
  if (denom < 1e-9) return false;
  const Eigen::Vector3d w = a - c;
  const double t = (b * w.dot(r) - w.dot(e)) / denom;
  X_world = a + t * e;
  return true;
}

bool SynthLineSequence::project(size_t k, const Eigen::Vector3d& X_world, Eigen::Vector2d& uv) const {
  const Eigen::Vector3d X = T_world_cam[k].inverse() * X_world;
  if (X.z() <= 1e-6 || !camera->project(X, uv)) return false;
  return uv.x() >= -0.5 && uv.y() >= -0.5 && uv.x() <= camera->width() - 0.5 && uv.y() <= camera->height() - 0.5;
}

namespace {
std::map<int, Edge3d> read_lines3d(const fs::path& file) {
  std::map<int, Edge3d> edges;
  for (const auto& row : io::read_text_rows(file, io::Separator::kComma)) {
    if (row.fields.size() < 8) throw InputError(file, row.line, "expected id,kind,x1,y1,z1,x2,y2,z2[,quad1,quad2]");
    double v[6];
    for (int i = 0; i < 6; ++i) v[i] = io::parse_double(row.fields[2 + i], file, row.line, "a coordinate");
    const int id = static_cast<int>(io::parse_int64(row.fields[0], file, row.line, "the edge id"));
    edges[id] = {Eigen::Vector3d(v[0], v[1], v[2]), Eigen::Vector3d(v[3], v[4], v[5])};
  }
  return edges;
}

void read_segments(const fs::path& file, TruthFrame& frame) {
  for (const auto& row : io::read_text_rows(file, io::Separator::kComma)) {
    if (row.fields.size() < 9) throw InputError(file, row.line, "expected x1,y1,x2,y2,id,kind,t1,t2,contrast");
    double v[4];
    for (int i = 0; i < 4; ++i) v[i] = io::parse_double(row.fields[i], file, row.line, "an endpoint coordinate");
    const int id = static_cast<int>(io::parse_int64(row.fields[4], file, row.line, "the edge id"));
    frame.truth.emplace_back(Eigen::Vector2d(v[0], v[1]), Eigen::Vector2d(v[2], v[3]), id);
    frame.contrast.push_back(static_cast<float>(io::parse_double(row.fields[8], file, row.line, "the contrast")));
  }
}

std::vector<size_t> selected(size_t n, const SynthFrameSelection& s) {
  std::vector<size_t> out;
  for (size_t i = s.first; i < n && (s.count == 0 || out.size() < s.count); i += std::max<size_t>(s.step, 1))
    out.push_back(i);
  return out;
}
}  // namespace

SynthLineSequence load_synth_line_sequence(const fs::path& root, const SynthFrameSelection& select) {
  io::SequenceOptions options;
  options.mono = true;
  const io::EurocSequence seq(root, options);
  const fs::path mav = fs::exists(root / "mav0") ? root / "mav0" : root;
  if (!seq.ground_truth()) throw InputError(mav / "state_groundtruth_estimate0" / "data.csv", "file not found");
  SynthLineSequence out;
  out.camera = seq.calibration().cam0;
  out.edges = read_lines3d(mav / "lines3d.csv");
  const auto& gt = *seq.ground_truth();
  size_t g = 0;
  for (size_t i : selected(seq.size(), select)) {
    // Frame stamps are rows of the 200 Hz ground truth (docs/synth.md): take the nearest.
    const double t = seq.timestamp(i);
    while (g + 1 < gt.stamps.size() && std::abs(gt.stamps[g + 1] - t) <= std::abs(gt.stamps[g] - t)) ++g;
    if (gt.stamps.empty() || std::abs(gt.stamps[g] - t) > 1e-4)
      throw InputError(mav / "state_groundtruth_estimate0" / "data.csv",
                       "no ground-truth pose at frame time " + std::to_string(t));
    TruthFrame frame;
    frame.image = seq.frame(i).left;
    read_segments(mav / "cam0" / "lines" / (seq.image_path(i).stem().string() + ".csv"), frame);
    out.frames.push_back(std::move(frame));
    out.indices.push_back(i);
    out.T_world_cam.push_back(gt.poses[g]);
  }
  if (out.frames.empty()) throw InputError(root, "no frame selected");
  return out;
}

SynthLineSequence render_synth_line_sequence(synth::Generator& generator, const std::vector<size_t>& indices) {
  SynthLineSequence out;
  out.camera = generator.camera(0);
  for (const auto& e : generator.scene().edges) out.edges[e.id] = {e.a, e.b};
  synth::RenderOptions options;
  options.lines = true;
  for (size_t i : indices) {
    synth::RenderedFrame f = generator.render(i, options);
    TruthFrame frame;
    frame.image = f.cameras[0].image.clone();
    for (const auto& s : f.cameras[0].segments) {
      frame.truth.emplace_back(s.a, s.b, s.id);
      frame.contrast.push_back(s.contrast);
    }
    out.frames.push_back(std::move(frame));
    out.indices.push_back(i);
    out.T_world_cam.push_back(f.cameras[0].T_world_cam);
  }
  return out;
}

}  // namespace pllvo::lines
