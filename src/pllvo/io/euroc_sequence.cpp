#include "pllvo/io/euroc_sequence.h"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include <spdlog/spdlog.h>
#include <yaml-cpp/yaml.h>

#include "pllvo/camera/camera_yaml.h"
#include "pllvo/common/error.h"
#include "pllvo/common/yaml_config.h"
#include "pllvo/geometry/pose.h"
#include "pllvo/io/dataset_files.h"

namespace pllvo::io {

namespace fs = std::filesystem;

namespace {

/// OpenCV writes `%YAML:1.0` as its first line; yaml-cpp only knows `%YAML 1.2`. The line
/// is turned into a comment so that line numbers in parse errors stay right.
ConfigNode load_opencv_yaml(const fs::path& file) {
  std::ifstream in(file);
  if (!in) throw InputError(file, fs::exists(file) ? "cannot open" : "file not found");
  std::ostringstream text;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("%YAML:", 0) == 0) line = "#" + line;
    text << line << '\n';
  }
  YAML::Node root;
  try {
    root = YAML::Load(text.str());
  } catch (const YAML::ParserException& e) {
    throw InputError(file, e.mark.line + 1, "malformed YAML: " + e.msg);
  }
  if (!root.IsMap()) throw InputError(file, 1, "expected a YAML mapping at the top level");
  return ConfigNode(root, file);
}

Eigen::Isometry3d read_T_BS(const ConfigNode& node) {
  const ConfigNode t = node.child("T_BS");
  const int rows = t.require<int>("rows"), cols = t.require<int>("cols");
  const auto data = t.require<std::vector<double>>("data");
  if (rows != 4 || cols != 4 || data.size() != 16)
    throw InputError(node.file(), t.path("data"), "expected a 4x4 matrix (16 values), found rows " +
                                                      std::to_string(rows) + ", cols " + std::to_string(cols) +
                                                      ", " + std::to_string(data.size()) + " values");
  Eigen::Matrix4d M;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) M(r, c) = data[4 * r + c];
  const Eigen::Matrix3d R = M.topLeftCorner<3, 3>();
  if (!M.allFinite() || (M.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).norm() > 1e-9 ||
      (R * R.transpose() - Eigen::Matrix3d::Identity()).norm() > 1e-5 || R.determinant() < 0)
    throw InputError(node.file(), t.path("data"), "not a rigid transform (rotation not orthonormal or last row not 0 0 0 1)");
  // The printed digits leave R orthonormal to ~1e-10; snap it so inverses are exact.
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = geometry::nearest_rotation(R);
  T.translation() = M.topRightCorner<3, 1>();
  return T;
}

template <typename T>
std::vector<T> require_values(const ConfigNode& node, const std::string& key, size_t count, const char* layout) {
  const auto v = node.require<std::vector<T>>(key);
  if (v.size() != count)
    throw InputError(node.file(), node.path(key), "expected " + std::string(layout) + ", found " +
                                                      std::to_string(v.size()) + " values");
  return v;
}

/// One camera stream: the cam folder's data.csv with its image files.
struct CameraStream {
  fs::path csv;
  EurocCameraSensor sensor;
  std::vector<int64_t> ns;
  std::vector<fs::path> files;
  std::vector<long> lines;
};

CameraStream read_camera_stream(const fs::path& dir) {
  CameraStream s;
  s.csv = dir / "data.csv";
  const auto rows = read_text_rows(s.csv, Separator::kComma);
  s.sensor = read_euroc_sensor_yaml(dir / "sensor.yaml");
  for (const auto& row : rows) {
    if (row.fields.size() != 2)
      throw InputError(s.csv, row.line, "expected 'timestamp [ns],filename', found " +
                                            std::to_string(row.fields.size()) + " fields");
    s.ns.push_back(parse_int64(row.fields[0], s.csv, row.line, "a timestamp in nanoseconds"));
    if (row.fields[1].empty()) throw InputError(s.csv, row.line, "empty file name");
    const fs::path image = dir / "data" / row.fields[1];
    if (!fs::is_regular_file(image)) throw InputError(s.csv, row.line, "image file not found: " + image.string());
    s.files.push_back(image);
    s.lines.push_back(row.line);
  }
  if (s.ns.empty()) throw InputError(s.csv, "no frames listed (empty sequence)");
  require_strictly_increasing(s.ns, s.lines, s.csv);
  return s;
}

}  // namespace

EurocCameraSensor read_euroc_sensor_yaml(const fs::path& file) {
  const ConfigNode node = load_opencv_yaml(file);
  EurocCameraSensor s;
  s.T_body_cam = read_T_BS(node);
  std::string model = "pinhole";
  node.get("camera_model", model);
  if (model != "pinhole")
    throw InputError(file, std::string("camera_model"), "unsupported camera model '" + model + "' (expected pinhole)");
  const auto res = require_values<int>(node, "resolution", 2, "[width, height]");
  const auto k = require_values<double>(node, "intrinsics", 4, "[fu, fv, cu, cv]");
  const auto dist_model = node.require<std::string>("distortion_model");
  const auto dist = node.require<std::vector<double>>("distortion_coefficients");
  node.get("rate_hz", s.rate_hz);
  node.get("depth_factor", s.depth_factor);
  if (!(s.depth_factor >= 0)) throw InputError(file, std::string("depth_factor"), "must be positive");
  if (res[0] <= 0 || res[1] <= 0) throw InputError(file, std::string("resolution"), "must be positive");
  if (!(k[0] > 0 && k[1] > 0)) throw InputError(file, std::string("intrinsics"), "focal lengths must be positive");
  try {
    s.camera = camera::make_camera(dist_model, res[0], res[1], {k[0], k[1], k[2], k[3]}, dist);
  } catch (const InputError& e) {
    throw InputError(file, std::string(dist_model == "radial-tangential" || dist_model == "equidistant"
                                           ? "distortion_coefficients"
                                           : "distortion_model"),
                     e.what());
  }
  return s;
}

EurocSequence::EurocSequence(const fs::path& root, const SequenceOptions& options) : Sequence(root) {
  if (!fs::is_directory(root)) throw InputError(root, "dataset folder not found");
  const fs::path mav = fs::is_directory(root / "mav0") ? root / "mav0" : root;
  const CameraStream cam0 = read_camera_stream(mav / "cam0");
  calib_.cam0 = cam0.sensor.camera;
  calib_.T_body_cam0 = cam0.sensor.T_body_cam;

  std::vector<long> match;
  std::vector<int64_t> kept_ns;  // cam0 stamps of the frames kept
  if (!options.mono && fs::is_directory(mav / "cam1")) {
    const CameraStream cam1 = read_camera_stream(mav / "cam1");
    calib_.cam1 = cam1.sensor.camera;
    calib_.T_body_cam1 = cam1.sensor.T_body_cam;
    match = nearest_in_time(cam0.ns, cam1.ns, static_cast<int64_t>(std::llround(options.stereo_max_dt * 1e9)));
    size_t dropped = 0;
    for (size_t i = 0; i < cam0.ns.size(); ++i) {
      if (match[i] < 0) {
        ++dropped;
        continue;
      }
      stamps_.push_back(static_cast<double>(cam0.ns[i]) / 1e9);
      kept_ns.push_back(cam0.ns[i]);
      left_files_.push_back(cam0.files[i]);
      right_files_.push_back(cam1.files[match[i]]);
    }
    if (stamps_.empty())
      throw InputError(cam1.csv, "no cam1 frame lies within " + std::to_string(options.stereo_max_dt) +
                                     " s of a cam0 frame: cannot pair the stereo images (use mono)");
    if (dropped)
      spdlog::warn("{}: {} of {} cam0 frames have no cam1 frame within {} s and are skipped", root.string(),
                   dropped, cam0.ns.size(), options.stereo_max_dt);
  } else {
    for (size_t i = 0; i < cam0.ns.size(); ++i) stamps_.push_back(static_cast<double>(cam0.ns[i]) / 1e9);
    kept_ns = cam0.ns;
    left_files_ = cam0.files;
  }
  // Depth images beside cam0's (pllvo synth --depth): one per frame, named by its stamp.
  const fs::path depth_dir = mav / "cam0" / "depth";
  if (options.depth && !options.mono && fs::is_directory(depth_dir)) {
    calib_.depth_factor = cam0.sensor.depth_factor > 0 ? cam0.sensor.depth_factor : 1000.0;
    for (const int64_t ns : kept_ns) {
      const fs::path file = depth_dir / (std::to_string(ns) + ".png");
      if (!fs::is_regular_file(file)) throw InputError(file, "depth image of a listed cam0 frame not found");
      depth_files_.push_back(file);
    }
  }
  calib_.rate_hz = cam0.sensor.rate_hz > 0 ? cam0.sensor.rate_hz : mean_rate(stamps_);

  const fs::path gt = mav / "state_groundtruth_estimate0" / "data.csv";
  if (fs::exists(gt)) ground_truth_ = read_euroc_csv(gt, &calib_.T_body_cam0);
}

}  // namespace pllvo::io
