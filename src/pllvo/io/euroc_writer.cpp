#include "pllvo/io/euroc_writer.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <system_error>

#include <opencv2/imgcodecs.hpp>

#include "pllvo/common/error.h"

namespace fs = std::filesystem;

namespace pllvo::io {

namespace {

/// Shortest text that reads back to the same double, with a decimal point like EuRoC's files.
std::string number(double v) {
  char buf[64];
  const auto res = std::to_chars(buf, buf + sizeof buf, v);
  std::string s(buf, res.ptr);
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
  return s;
}

std::string list(const std::vector<double>& values) {
  std::string s = "[";
  for (size_t i = 0; i < values.size(); ++i) {
    if (i) s += ", ";
    s += number(values[i]);
  }
  return s + "]";
}

std::string T_BS_yaml(const Eigen::Isometry3d& T) {
  std::string s = "T_BS:\n  cols: 4\n  rows: 4\n  data: [";
  for (int r = 0; r < 4; ++r) {
    if (r) s += ",\n         ";
    for (int c = 0; c < 4; ++c) {
      if (c) s += ", ";
      s += number(T.matrix()(r, c));
    }
  }
  return s + "]\n";
}

void write_text(const fs::path& file, const std::string& text) {
  std::ofstream f(file);
  f << text;
  if (!f) throw InputError(file, "cannot write");
}

std::string fixed(double v, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

}  // namespace

std::string euroc_camera_yaml(const EurocCamera& camera, const std::string& comment) {
  const auto& m = *camera.model;
  const auto& k = m.intrinsics();
  std::vector<double> dist = m.distortion();
  std::string model = "radial-tangential";
  if (m.name() == "kannala-brandt") model = "equidistant";
  else if (dist.size() == 5 && dist[4] == 0.0) dist.resize(4);
  std::string s = "%YAML:1.0\n# General sensor definitions.\nsensor_type: camera\ncomment: " + comment + "\n\n";
  s += "# Sensor extrinsics wrt. the body-frame.\n" + T_BS_yaml(camera.T_body_cam) + "\n";
  s += "# Camera specific definitions.\n";
  const bool whole = camera.rate_hz == std::floor(camera.rate_hz) && camera.rate_hz < 1e9;
  s += "rate_hz: " + (whole ? std::to_string(static_cast<long long>(camera.rate_hz)) : number(camera.rate_hz)) + "\n";
  s += "resolution: [" + std::to_string(m.width()) + ", " + std::to_string(m.height()) + "]\n";
  s += "camera_model: pinhole\n";
  s += "intrinsics: " + list({k.fx, k.fy, k.cx, k.cy}) + " #fu, fv, cu, cv\n";
  s += "distortion_model: " + model + "\n";
  s += "distortion_coefficients: " + list(dist) + "\n";
  return s;
}

EurocWriter::EurocWriter(fs::path root, std::vector<EurocCamera> cameras, bool overwrite)
    : cameras_(std::move(cameras)), overwrite_(overwrite) {
  root = root.lexically_normal();
  if (!root.has_filename()) root = root.parent_path();
  root_ = root;
  if (cameras_.empty()) throw InternalError("EurocWriter: no camera");
  if (fs::exists(root_) && !overwrite_)
    throw InputError(root_, "already exists (choose another output folder or overwrite it)");
  staging_ = root_.parent_path() / (root_.filename().string() + ".partial");
  std::error_code ec;
  fs::remove_all(staging_, ec);  // left over from an interrupted run
  fs::create_directories(staging_ / "mav0", ec);
  if (ec) throw InputError(staging_, "cannot create folder: " + ec.message());

  for (size_t c = 0; c < cameras_.size(); ++c) {
    const fs::path dir = camera_dir(c);
    fs::create_directories(dir / "data", ec);
    if (ec) throw InputError(dir, "cannot create folder: " + ec.message());
    const std::string name = "cam" + std::to_string(c);
    write_text(dir / "sensor.yaml",
               euroc_camera_yaml(cameras_[c], cameras_[c].comment.empty() ? "pllvo " + name : cameras_[c].comment));
    frame_csv_.emplace_back(dir / "data.csv");
    frame_csv_.back() << "#timestamp [ns],filename\n";
  }
  const fs::path gt = staging_ / "mav0" / "state_groundtruth_estimate0";
  fs::create_directories(gt, ec);
  if (ec) throw InputError(gt, "cannot create folder: " + ec.message());
  write_text(gt / "sensor.yaml",
             "%YAML:1.0\n# General sensor definitions.\nsensor_type: visual-inertial\ncomment: exact ground truth "
             "(pose of the body frame in the world; velocity in the world frame; biases zero)\n\n"
             "# Sensor extrinsics wrt. the body-frame.\n" +
                 T_BS_yaml(Eigen::Isometry3d::Identity()));
  gt_csv_.open(gt / "data.csv");
  gt_csv_ << "#timestamp, p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x [], q_RS_y [], q_RS_z [], "
             "v_RS_R_x [m s^-1], v_RS_R_y [m s^-1], v_RS_R_z [m s^-1], b_w_RS_S_x [rad s^-1], "
             "b_w_RS_S_y [rad s^-1], b_w_RS_S_z [rad s^-1], b_a_RS_S_x [m s^-2], b_a_RS_S_y [m s^-2], "
             "b_a_RS_S_z [m s^-2]\n";
  write_text(staging_ / "mav0" / "body.yaml", "%YAML:1.0\ncomment: pllvo synthetic body\n");
}

EurocWriter::~EurocWriter() {
  if (committed_) return;
  for (auto& f : frame_csv_) f.close();
  gt_csv_.close();
  std::error_code ec;
  fs::remove_all(staging_, ec);
}

fs::path EurocWriter::camera_dir(size_t c) const { return staging_ / "mav0" / ("cam" + std::to_string(c)); }

void EurocWriter::add_frame(int64_t stamp_ns, const std::vector<cv::Mat>& images) {
  if (images.size() != cameras_.size())
    throw InternalError("EurocWriter: expected " + std::to_string(cameras_.size()) + " images per frame");
  if (stamp_ns <= last_frame_ns_) throw InternalError("EurocWriter: frame timestamps must increase");
  last_frame_ns_ = stamp_ns;
  const std::string name = std::to_string(stamp_ns) + ".png";
  for (size_t c = 0; c < images.size(); ++c) {
    const auto& m = *cameras_[c].model;
    if (images[c].cols != m.width() || images[c].rows != m.height() ||
        (images[c].type() != CV_8UC1 && images[c].type() != CV_16UC1))
      throw InternalError("EurocWriter: image " + std::to_string(c) + " does not match its camera");
    const fs::path file = camera_dir(c) / "data" / name;
    if (!cv::imwrite(file.string(), images[c], {cv::IMWRITE_PNG_COMPRESSION, 1}))
      throw InputError(file, "cannot write image");
    frame_csv_[c] << stamp_ns << "," << name << "\n";
  }
}

void EurocWriter::add_ground_truth(const EurocGroundTruth& g) {
  if (g.stamp_ns <= last_gt_ns_) throw InternalError("EurocWriter: ground-truth timestamps must increase");
  last_gt_ns_ = g.stamp_ns;
  Eigen::Quaterniond q(g.T_world_body.linear());
  q.normalize();
  if (q.w() < 0) q.coeffs() *= -1;
  const Eigen::Vector3d& p = g.T_world_body.translation();
  gt_csv_ << g.stamp_ns;
  for (double v : {p.x(), p.y(), p.z()}) gt_csv_ << ',' << fixed(v, 9);
  for (double v : {q.w(), q.x(), q.y(), q.z()}) gt_csv_ << ',' << fixed(v, 12);
  for (const auto* vec : {&g.velocity, &g.gyro_bias, &g.accel_bias})
    for (int k = 0; k < 3; ++k) gt_csv_ << ',' << fixed((*vec)[k], 9);
  gt_csv_ << '\n';
}

void EurocWriter::commit() {
  if (committed_) return;
  for (auto& f : frame_csv_) {
    f.close();
    if (f.fail()) throw InputError(staging_, "cannot write data.csv");
  }
  gt_csv_.close();
  if (gt_csv_.fail()) throw InputError(staging_, "cannot write state_groundtruth_estimate0/data.csv");
  std::error_code ec;
  if (fs::exists(root_)) {
    if (!overwrite_) throw InputError(root_, "already exists");
    fs::remove_all(root_, ec);
    if (ec) throw InputError(root_, "cannot replace: " + ec.message());
  }
  fs::rename(staging_, root_, ec);
  if (ec) throw InputError(root_, "cannot move the finished sequence into place: " + ec.message());
  committed_ = true;
}

}  // namespace pllvo::io
