#include "pllvo/synth/sequence_writer.h"

#include <cmath>
#include <cstdio>
#include <fstream>

#include <opencv2/imgcodecs.hpp>

#include "pllvo/common/error.h"
#include "pllvo/io/euroc_writer.h"
#include "pllvo/synth/generator.h"

namespace fs = std::filesystem;

namespace pllvo::synth {

namespace {

void write_lines(const fs::path& file, const std::vector<TruthSegment>& segments) {
  std::ofstream f(file);
  f << "#x1,y1,x2,y2,id,kind,t1,t2,contrast\n";
  char buf[256];
  for (const auto& s : segments) {
    std::snprintf(buf, sizeof buf, "%.3f,%.3f,%.3f,%.3f,%d,%d,%.6f,%.6f,%.2f\n", s.a.x(), s.a.y(), s.b.x(), s.b.y(),
                  s.id, static_cast<int>(s.kind), s.t0, s.t1, s.contrast);
    f << buf;
  }
  if (!f) throw InputError(file, "cannot write");
}

void write_lines3d(const fs::path& file, const Scene& scene) {
  std::ofstream f(file);
  f << "#id,kind,x1,y1,z1,x2,y2,z2,quad1,quad2\n";
  char buf[320];
  for (const auto& e : scene.edges) {
    std::snprintf(buf, sizeof buf, "%d,%d,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%d,%d\n", e.id, static_cast<int>(e.kind),
                  e.a.x(), e.a.y(), e.a.z(), e.b.x(), e.b.y(), e.b.z(), e.quads[0], e.quads[1]);
    f << buf;
  }
  if (!f) throw InputError(file, "cannot write");
}

cv::Mat depth_mm(const cv::Mat& depth) {
  cv::Mat mm;
  depth.convertTo(mm, CV_16U, 1000.0);  // rounds; > 65.535 m saturates
  return mm;
}

}  // namespace

void write_sequence(const SequenceSpec& spec, const fs::path& out_dir, const WriteOptions& options) {
  validate(spec);
  Generator gen(spec);
  std::vector<io::EurocCamera> cams;
  for (size_t c = 0; c < gen.num_cameras(); ++c)
    cams.push_back({gen.camera(c), gen.T_body_cam(c), spec.camera.rate_hz,
                    "pllvo synth " + spec.name + " cam" + std::to_string(c)});
  io::EurocWriter writer(out_dir, cams, options.overwrite);
  {
    std::ofstream f(writer.staging_root() / "synth.yaml");
    f << "# pllvo synth: the spec this sequence was rendered from (pllvo synth --config reads it)\n" << to_yaml(spec);
  }
  if (spec.output.lines) write_lines3d(writer.staging_root() / "mav0" / "lines3d.csv", gen.scene());

  std::vector<std::ofstream> exposure_csv;
  for (size_t c = 0; c < gen.num_cameras(); ++c) {
    if (spec.output.lines) fs::create_directories(writer.camera_dir(c) / "lines");
    if (spec.output.depth) fs::create_directories(writer.camera_dir(c) / "depth");
    exposure_csv.emplace_back(writer.camera_dir(c) / "exposure.csv");
    exposure_csv.back() << "#timestamp [ns],exposure_ms,gain,light_level,subframes\n";
  }

  RenderOptions ro;
  ro.lines = spec.output.lines;
  ro.depth = spec.output.depth;
  const size_t n = gen.num_frames();
  for (size_t i = 0; i < n; ++i) {
    const RenderedFrame f = gen.render(i, ro);
    std::vector<cv::Mat> images;
    for (const auto& cf : f.cameras) images.push_back(cf.image);
    writer.add_frame(f.stamp_ns, images);
    const std::string stem = std::to_string(f.stamp_ns);
    char buf[160];
    std::snprintf(buf, sizeof buf, "%lld,%.6f,%.6f,%.6f,%d\n", static_cast<long long>(f.stamp_ns),
                  f.exposure.exposure_ms, f.exposure.gain, f.exposure.light_level, f.subframes);
    for (size_t c = 0; c < f.cameras.size(); ++c) {
      exposure_csv[c] << buf;
      if (spec.output.lines) write_lines(writer.camera_dir(c) / "lines" / (stem + ".csv"), f.cameras[c].segments);
      if (spec.output.depth) {
        const fs::path file = writer.camera_dir(c) / "depth" / (stem + ".png");
        if (!cv::imwrite(file.string(), depth_mm(f.cameras[c].depth), {cv::IMWRITE_PNG_COMPRESSION, 1}))
          throw InputError(file, "cannot write image");
      }
    }
    if (options.progress) options.progress(spec.name, i + 1, n);
  }
  for (auto& f : exposure_csv) {
    f.close();
    if (f.fail()) throw InputError(writer.staging_root(), "cannot write exposure.csv");
  }

  // Ground truth at its own rate over the frames' time span (EuRoC: 200 Hz).
  const double t_end = gen.time(n - 1);
  const double dt = 1.0 / spec.output.groundtruth_rate_hz;
  for (size_t k = 0; k * dt <= t_end + 1e-9; ++k) {
    const double t = static_cast<double>(k) * dt;
    io::EurocGroundTruth g;
    g.stamp_ns = gen.stamp_ns(t);
    g.T_world_body = gen.T_world_body(t);
    g.velocity = gen.body_velocity(t);
    writer.add_ground_truth(g);
  }
  writer.commit();
}

std::vector<fs::path> write_suite(const fs::path& out_root, const std::function<void(SequenceSpec&)>& customise,
                                  const WriteOptions& options) {
  std::vector<fs::path> written;
  for (const auto& name : suite_presets()) {
    SequenceSpec spec = preset(name);
    if (customise) customise(spec);
    const fs::path dir = out_root / name;
    write_sequence(spec, dir, options);
    written.push_back(dir);
  }
  return written;
}

}  // namespace pllvo::synth
