#include "pllvo/io/sequence_info.h"

#include <algorithm>
#include <cstdio>
#include <sstream>

#include "pllvo/camera/stereo_rectifier.h"
#include "pllvo/io/dataset_files.h"

namespace pllvo::io {

namespace {

std::string format(const char* fmt, auto... args) {
  char buf[512];
  std::snprintf(buf, sizeof buf, fmt, args...);
  return buf;
}

std::string describe_camera(const camera::CameraModel& cam) {
  const auto& k = cam.intrinsics();
  std::string s = format("%s  fx %.12g  fy %.12g  cx %.12g  cy %.12g  distortion [", cam.name().c_str(), k.fx, k.fy,
                         k.cx, k.cy);
  const auto d = cam.distortion();
  for (size_t i = 0; i < d.size(); ++i) s += format(i ? ", %.12g" : "%.12g", d[i]);
  return s + "]";
}

}  // namespace

std::string describe_sequence(const Sequence& seq) {
  const auto& calib = seq.calibration();
  std::ostringstream out;
  const auto line = [&](const char* name, const std::string& value) { out << format("%-13s", name) << value << "\n"; };
  line("dataset", seq.root().string());
  std::string sensors = calib.stereo() ? "stereo" : "mono";
  if (calib.has_depth()) sensors += calib.stereo() ? ", depth" : ", depth: RGB-D";
  line("format", seq.format() + " (" + sensors + ")");
  line("frames", std::to_string(seq.size()));
  if (!seq.empty()) {
    const double t0 = seq.timestamp(0), t1 = seq.timestamp(seq.size() - 1);
    line("duration", format("%.3f s  (%.6f .. %.6f)", t1 - t0, t0, t1));
  }
  line("rate", format("%.6g Hz  (timestamps: %.6g Hz)", calib.rate_hz, mean_rate(seq.timestamps())));
  line("resolution", format("%d x %d", calib.cam0->width(), calib.cam0->height()));
  line("cam0", describe_camera(*calib.cam0));
  if (calib.stereo()) {
    line("cam1", describe_camera(*calib.cam1));
    const camera::StereoRectifier rect(calib.cam0, calib.cam1, calib.T_body_cam0, calib.T_body_cam1);
    const auto& k = rect.rectified_intrinsics();
    line("baseline", format("%.6f m  (rectified fx %.6g  fy %.6g  cx %.6g  cy %.6g)", rect.baseline(), k.fx, k.fy,
                            k.cx, k.cy));
  }
  if (calib.has_depth()) {
    const auto& files = seq.depth_files();
    const auto with = std::count_if(files.begin(), files.end(), [](const auto& f) { return !f.empty(); });
    line("depth", format("%td of %zu frames, metres = value / %g", with, seq.size(), calib.depth_factor));
  }
  const auto& gt = seq.ground_truth();
  if (gt && gt->has_stamps())
    line("ground truth", format("%zu poses T_world_cam0  (%.6f .. %.6f)", gt->size(), gt->stamps.front(),
                                gt->stamps.back()));
  else
    line("ground truth", gt ? format("%zu poses T_world_cam0", gt->size()) : std::string("none"));
  return out.str();
}

}  // namespace pllvo::io
