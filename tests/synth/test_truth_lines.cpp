// Ground-truth 2-D segments: they lie on the image's edges, keep their ids, follow the
// lens distortion, and stop where something hides them.
#include <gtest/gtest.h>

#include <map>
#include <set>

#include <opencv2/imgproc.hpp>

#include "synth_fixtures.h"

using namespace pllvo::synth;
using namespace pllvo::synth::testing;

namespace {

Texture flat(double value) {
  Texture t;
  t.image = cv::Mat(16, 16, CV_32F, cv::Scalar(value));
  return t;
}

/// Distance from the segment to the strongest gradient along its normal (within +-range px),
/// averaged over samples; `hits` counts samples whose peak is within `hit` px.
struct EdgeFit {
  double mean_offset = 0;
  int hits = 0, samples = 0;
};

struct Gradients {
  explicit Gradients(const cv::Mat& clean) {
    cv::Sobel(clean, gx, CV_32F, 1, 0);
    cv::Sobel(clean, gy, CV_32F, 0, 1);
  }
  cv::Mat gx, gy;
};

EdgeFit fit_to_gradient(const Gradients& g, const TruthSegment& s, double range = 3.0, double hit = 1.0) {
  const cv::Mat& gx = g.gx;
  const cv::Mat& gy = g.gy;
  const cv::Mat& clean = gx;
  EdgeFit fit;
  const Eigen::Vector2d d = (s.b - s.a).normalized(), n(-d.y(), d.x());
  const double len = (s.b - s.a).norm();
  for (double a = 3; a < len - 3; a += 2) {
    double best = -1, best_off = 0;
    for (double off = -range; off <= range + 1e-9; off += 0.25) {
      const Eigen::Vector2d p = s.a + a * d + off * n;
      const int x = static_cast<int>(std::lround(p.x())), y = static_cast<int>(std::lround(p.y()));
      if (x < 1 || y < 1 || x >= clean.cols - 1 || y >= clean.rows - 1) continue;
      cv::Mat patch_x, patch_y;
      cv::getRectSubPix(gx, cv::Size(1, 1), cv::Point2f(static_cast<float>(p.x()), static_cast<float>(p.y())), patch_x);
      cv::getRectSubPix(gy, cv::Size(1, 1), cv::Point2f(static_cast<float>(p.x()), static_cast<float>(p.y())), patch_y);
      const double mag = std::abs(patch_x.at<float>(0) * n.x() + patch_y.at<float>(0) * n.y());
      if (mag > best) best = mag, best_off = off;
    }
    if (best < 0) continue;
    ++fit.samples;
    fit.mean_offset += std::abs(best_off);
    if (std::abs(best_off) <= hit) ++fit.hits;
  }
  if (fit.samples) fit.mean_offset /= fit.samples;
  return fit;
}

/// True when another, roughly parallel edge runs within `gap` px of s (thin boards, panel faces seen at a
/// grazing angle, book spines): the image cannot tell such edges apart.
bool has_close_neighbour(const std::vector<TruthSegment>& all, const TruthSegment& s, double gap) {
  const Eigen::Vector2d d = (s.b - s.a).normalized(), n(-d.y(), d.x());
  const double len = (s.b - s.a).norm();
  for (const auto& o : all) {
    if (o.id == s.id || std::abs((o.b - o.a).normalized().dot(d)) < 0.9) continue;
    for (double t = 0; t <= 1.0; t += 0.05) {
      const Eigen::Vector2d p = o.a + t * (o.b - o.a) - s.a;
      const double along = p.dot(d);
      if (along > -gap && along < len + gap && std::abs(p.dot(n)) < gap) return true;
    }
  }
  return false;
}

}  // namespace

TEST(SynthTruthLines, PosterBordersLieOnTheImageEdgesAndOcclusionCutsThem) {
  // Dark wall, bright poster 1 cm in front, and a grey box in front of the poster's top edge
  // (no surface saturates: a clipped edge would shift its gradient peak).
  SceneBuilder b;
  b.add_facing({0, 3, 1.5}, -Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ(), 8, 5, flat(0.1));
  const int poster = b.add_facing({0.1, 2.99, 1.6}, -Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ(), 1.2, 0.9,
                                  flat(0.45));
  // Box: front face 0.3 x 0.3 m at y = 2.0, x in [-0.05, 0.25], z in [1.72, 2.02]; from the
  // camera at (0, 0, 1.5) it hides x in 1.495 * [-0.05, 0.25] of the poster's top edge (z = 2.05).
  const int box = b.add_facing({0.1, 2.0, 1.87}, -Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ(), 0.3, 0.3,
                               flat(0.5));
  Scene scene = b.finish();
  SequenceSpec spec = quiet_spec();
  spec.sensor.exposure_ms = 2;
  Generator gen(spec, scene, std::make_shared<StaticPath>(camera_facing_wall(0, 0.05, 0.08, 0.1)));
  RenderOptions opt;
  opt.lines = true;
  opt.clean = true;
  opt.noise = false;
  const RenderedFrame f = gen.render(0, opt);
  const auto& segs = f.cameras[0].segments;

  // The poster's top border (the edge of the quad between its corners 0 and 1).
  const Quad& pq = gen.scene().quads[poster];
  int top_id = -1;
  for (const auto& e : gen.scene().edges)
    if (e.kind == EdgeKind::geometric && e.quads[0] == poster &&
        ((e.a - pq.corner(0)).norm() < 1e-9 || (e.b - pq.corner(0)).norm() < 1e-9) &&
        ((e.a - pq.corner(1)).norm() < 1e-9 || (e.b - pq.corner(1)).norm() < 1e-9))
      top_id = e.id;
  ASSERT_GE(top_id, 0);

  const Gradients grad(f.cameras[0].clean);
  const auto& top = gen.scene().edges[top_id];
  const double scale = 2.99 / 2.0;
  double lo = (-0.05 * scale - top.a.x()) / (top.b.x() - top.a.x()), hi = (0.25 * scale - top.a.x()) / (top.b.x() - top.a.x());
  if (lo > hi) std::swap(lo, hi);
  int poster_pieces = 0, top_pieces = 0;
  double covered = 0;
  for (const auto& s : segs) {
    const auto& e = gen.scene().edges[s.id];
    if (e.quads[0] != poster) continue;
    ++poster_pieces;
    const EdgeFit fit = fit_to_gradient(grad, s);
    ASSERT_GT(fit.samples, 5);
    EXPECT_GE(fit.hits, 0.95 * fit.samples) << "edge " << s.id;
    EXPECT_LT(fit.mean_offset, 0.4) << "edge " << s.id;
    EXPECT_GT(s.contrast, 60);  // bright poster on a dark wall
    if (s.id == top_id) {
      ++top_pieces;
      covered += std::abs(s.t1 - s.t0);
      // No visible piece of the top border runs behind the box.
      const double a = std::min(s.t0, s.t1), c = std::max(s.t0, s.t1);
      EXPECT_TRUE(c <= lo + 0.01 || a >= hi - 0.01) << a << " " << c;
    }
  }
  EXPECT_GE(poster_pieces, 5);  // 3 borders whole + the top border in (at least) two pieces
  EXPECT_GE(top_pieces, 2);
  EXPECT_NEAR(covered, 1.0 - (hi - lo), 0.02);
  // The box's own borders are seen, in front of everything.
  int box_pieces = 0;
  for (const auto& s : segs) box_pieces += gen.scene().edges[s.id].quads[0] == box;
  EXPECT_EQ(box_pieces, 4);
}

TEST(SynthTruthLines, SegmentsFollowTheDistortedEdges) {
  // A straight border near the image corner bends: the truth comes in several straight pieces,
  // each within 0.5 px of the projected curve.
  SceneBuilder b;
  b.add_facing({0, 3, 1.5}, -Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ(), 8, 5, flat(0.1));
  b.add_facing({0, 2.99, 1.5}, -Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ(), 5.0, 2.4, flat(0.45));
  Scene scene = b.finish();
  Generator gen(quiet_spec(), scene, std::make_shared<StaticPath>(camera_facing_wall()));
  RenderOptions opt;
  opt.lines = true;
  const RenderedFrame f = gen.render(0, opt);
  const auto& cam = *gen.camera(0);
  const Eigen::Isometry3d T_cw = f.cameras[0].T_world_cam.inverse();
  std::map<int, int> pieces;
  for (const auto& s : f.cameras[0].segments) {
    ++pieces[s.id];
    const auto& e = gen.scene().edges[s.id];
    // Points of the 3-D edge between t0 and t1 project onto the straight piece within 0.5 px.
    const Eigen::Vector2d d = (s.b - s.a).normalized(), n(-d.y(), d.x());
    for (double t = 0; t <= 1.0; t += 0.1) {
      Eigen::Vector2d uv;
      ASSERT_TRUE(cam.project(T_cw * (e.a + (s.t0 + t * (s.t1 - s.t0)) * (e.b - e.a)), uv));
      EXPECT_LT(std::abs(n.dot(uv - s.a)), 0.55);
    }
  }
  int bent = 0;
  for (const auto& [id, count] : pieces) bent += count > 1;
  EXPECT_GE(bent, 2);  // the long borders near the top and bottom need several pieces
}

namespace {

/// Checks every isolated, strong, unsaturated edge of a frame against the image gradient;
/// returns {checked, good}.
std::pair<int, int> check_room_frame(const Generator& gen, const RenderedFrame& f) {
  const Gradients grad(f.cameras[0].clean);
  // Near-saturated surfaces (lamps, windows) clip their edges, which moves the gradient peak.
  cv::Mat saturated;
  cv::dilate(f.cameras[0].clean > 250, saturated, cv::Mat(), cv::Point(-1, -1), 3);
  int strong = 0, good = 0;
  for (const auto& s : f.cameras[0].segments) {
    if (s.kind == EdgeKind::texture_line || s.contrast < 25 || (s.b - s.a).norm() < 30) continue;
    const Eigen::Vector2d mid = 0.5 * (s.a + s.b);
    if (saturated.at<uint8_t>(static_cast<int>(mid.y()), static_cast<int>(mid.x()))) continue;
    if (has_close_neighbour(f.cameras[0].segments, s, 3.5)) continue;
    ++strong;
    const EdgeFit fit = fit_to_gradient(grad, s, 1.5, 0.75);
    // Textured faces (book spines) modulate the contrast along an edge: most samples, not all.
    const bool ok = fit.samples > 0 && fit.hits >= 0.7 * fit.samples;
    good += ok;
    if (!ok) {
      const auto& e = gen.scene().edges[s.id];
      ADD_FAILURE() << "frame " << f.index << " edge " << s.id << " kind " << int(s.kind) << " quads " << e.quads[0]
                    << " " << e.quads[1] << " contrast " << s.contrast << " from (" << s.a.transpose() << ") to ("
                    << s.b.transpose() << ") hits " << fit.hits << "/" << fit.samples << " mean offset "
                    << fit.mean_offset;
    }
  }
  return {strong, good};
}

}  // namespace

TEST(SynthTruthLines, RoomTruthIsOnImageEdgesWithStableIds) {
  SequenceSpec spec = preset("medium_normal");
  spec.duration_s = 2;
  spec.sensor.motion_blur = false;  // blur turns an edge's gradient peak into a plateau
  Generator gen(spec);
  RenderOptions opt;
  opt.lines = true;
  opt.clean = true;
  opt.noise = false;
  int strong = 0, good = 0;
  for (size_t frame : {10, 25, 38}) {
    const auto [s, g] = check_room_frame(gen, gen.render(frame, opt));
    strong += s, good += g;
  }
  EXPECT_GT(strong, 60);
  EXPECT_EQ(good, strong);
  // Consecutive frames see mostly the same edges under the same ids.
  const RenderedFrame f0 = gen.render(10, opt), f1 = gen.render(11, opt);
  std::set<int> ids0, ids1;
  for (const auto& s : f0.cameras[0].segments) ids0.insert(s.id);
  for (const auto& s : f1.cameras[0].segments) ids1.insert(s.id);
  int common = 0;
  for (int id : ids0) common += ids1.count(id);
  EXPECT_GT(common, 0.8 * ids0.size());
}
