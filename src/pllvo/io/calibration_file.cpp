#include "pllvo/io/calibration_file.h"

#include <fstream>
#include <sstream>

#include <opencv2/core.hpp>
#include <yaml-cpp/yaml.h>

#include "pllvo/camera/camera_yaml.h"
#include "pllvo/common/error.h"
#include "pllvo/common/yaml_config.h"
#include "pllvo/io/euroc_sequence.h"

namespace pllvo::io {
namespace {

std::string read_text(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw InputError(file, "cannot read the calibration file");
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

bool has_top_key(const std::string& text, const std::string& key) {
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(key + ":", 0) == 0) return true;
  return false;
}

camera::CameraPtr kalibr_camera(const ConfigNode& cam) {
  const std::string model = cam.require<std::string>("camera_model");
  if (model != "pinhole") throw InputError(cam.file(), cam.path("camera_model"), "only the pinhole model is read");
  std::vector<double> k, res, dist;
  cam.get("intrinsics", k);
  cam.get("resolution", res);
  cam.get("distortion_coeffs", dist);
  if (k.size() != 4) throw InputError(cam.file(), cam.path("intrinsics"), "expected [fu, fv, pu, pv]");
  if (res.size() != 2) throw InputError(cam.file(), cam.path("resolution"), "expected [width, height]");
  std::string dm = "none";
  cam.get("distortion_model", dm);
  camera::PinholeIntrinsics in;
  in.fx = k[0], in.fy = k[1], in.cx = k[2], in.cy = k[3];
  try {
    return camera::make_camera(dm, static_cast<int>(res[0]), static_cast<int>(res[1]), in, dist);
  } catch (const InputError& e) {
    throw InputError(cam.file(), cam.path("distortion_model"), e.what());
  }
}

Calibration load_kalibr(const std::filesystem::path& file) {
  const ConfigNode root = ConfigNode::load_file(file);
  Calibration c;
  c.cam0 = kalibr_camera(root.child("cam0"));
  if (root.has("cam1")) {
    const ConfigNode cam1 = root.child("cam1");
    c.cam1 = kalibr_camera(cam1);
    std::vector<std::vector<double>> rows;
    cam1.get("T_cn_cnm1", rows);
    Eigen::Matrix4d T;
    if (rows.size() != 4) throw InputError(file, cam1.path("T_cn_cnm1"), "expected a 4x4 matrix");
    for (int r = 0; r < 4; ++r) {
      if (rows[r].size() != 4) throw InputError(file, cam1.path("T_cn_cnm1"), "expected a 4x4 matrix");
      for (int col = 0; col < 4; ++col) T(r, col) = rows[r][col];
    }
    if (!T.allFinite()) throw InputError(file, cam1.path("T_cn_cnm1"), "not finite");
    Eigen::Isometry3d T_right_left;
    T_right_left.matrix() = T;
    c.T_body_cam1 = T_right_left.inverse();  // body = cam0
  }
  return c;
}

Calibration load_opencv(const std::filesystem::path& file) {
  cv::FileStorage fs;
  try {
    fs.open(file.string(), cv::FileStorage::READ);
  } catch (const cv::Exception& e) {
    throw InputError(file, std::string("malformed OpenCV calibration file: ") + e.what());
  }
  if (!fs.isOpened()) throw InputError(file, "cannot read as an OpenCV calibration file");
  cv::Mat K, dist;
  int w = 0, h = 0;
  std::string model = "radtan";
  try {
    fs["camera_matrix"] >> K;
    fs["distortion_coefficients"] >> dist;
    fs["image_width"] >> w;
    fs["image_height"] >> h;
    fs["distortion_model"] >> model;  // absent in OpenCV's own files: radtan
  } catch (const cv::Exception& e) {
    throw InputError(file, std::string("malformed OpenCV calibration file: ") + e.what());
  }
  if (K.rows != 3 || K.cols != 3) throw InputError(file, "camera_matrix", "expected a 3x3 matrix");
  if (w <= 0 || h <= 0) throw InputError(file, "image_width", "image_width and image_height are required");
  K.convertTo(K, CV_64F);
  dist.convertTo(dist, CV_64F);
  camera::PinholeIntrinsics in;
  in.fx = K.at<double>(0, 0), in.fy = K.at<double>(1, 1), in.cx = K.at<double>(0, 2), in.cy = K.at<double>(1, 2);
  std::vector<double> d;
  if (!dist.empty()) d.assign(dist.begin<double>(), dist.end<double>());
  if (model.empty()) model = "radtan";
  while (model == "radtan" && d.size() > 5 && d.back() == 0.0) d.pop_back();
  Calibration c;
  try {
    c.cam0 = camera::make_camera(model, w, h, in, d);
  } catch (const InputError& e) {
    throw InputError(file, "distortion_coefficients", e.what());
  }
  return c;
}

}  // namespace

Calibration load_calibration_file(const std::filesystem::path& file) {
  if (!std::filesystem::is_regular_file(file)) throw InputError(file, "calibration file not found");
  const std::string text = read_text(file);
  if (has_top_key(text, "cam0")) return load_kalibr(file);
  if (has_top_key(text, "camera_matrix")) return load_opencv(file);
  Calibration c;
  if (has_top_key(text, "T_BS") || has_top_key(text, "intrinsics")) {
    const EurocCameraSensor sensor = read_euroc_sensor_yaml(file);
    c.cam0 = sensor.camera;
    c.T_body_cam0 = sensor.T_body_cam;
    c.rate_hz = sensor.rate_hz;
    return c;
  }
  c.cam0 = camera::load_camera_yaml(file);
  return c;
}

void save_kalibr_camchain(const camera::CameraModel& cam0, const camera::CameraModel* cam1,
                          const Eigen::Isometry3d& T_left_right, const std::filesystem::path& file) {
  YAML::Emitter out;
  out.SetDoublePrecision(17);
  const auto camera = [&](const camera::CameraModel& c) {
    const auto& k = c.intrinsics();
    out << YAML::Key << "camera_model" << YAML::Value << "pinhole";
    out << YAML::Key << "intrinsics" << YAML::Value << YAML::Flow << std::vector<double>{k.fx, k.fy, k.cx, k.cy};
    out << YAML::Key << "distortion_model" << YAML::Value << (c.name() == "kannala-brandt" ? "equidistant" : "radtan");
    out << YAML::Key << "distortion_coeffs" << YAML::Value << YAML::Flow << c.distortion();
    out << YAML::Key << "resolution" << YAML::Value << YAML::Flow << std::vector<int>{c.width(), c.height()};
  };
  out << YAML::BeginMap << YAML::Key << "cam0" << YAML::Value << YAML::BeginMap;
  camera(cam0);
  out << YAML::EndMap;
  if (cam1) {
    out << YAML::Key << "cam1" << YAML::Value << YAML::BeginMap;
    const Eigen::Matrix4d T = T_left_right.inverse().matrix();
    out << YAML::Key << "T_cn_cnm1" << YAML::Value << YAML::BeginSeq;
    for (int r = 0; r < 4; ++r) out << YAML::Flow << std::vector<double>{T(r, 0), T(r, 1), T(r, 2), T(r, 3)};
    out << YAML::EndSeq;
    camera(*cam1);
    out << YAML::EndMap;
  }
  out << YAML::EndMap;
  std::ofstream f(file);
  if (!f) throw InputError(file, "cannot write");
  f << out.c_str() << "\n";
}

}  // namespace pllvo::io
