#pragma once
// Writes a dataset in the EuRoC ASL layout:
//   <root>/mav0/cam0/sensor.yaml, data.csv, data/<ns>.png   (and cam1 for stereo)
//   <root>/mav0/state_groundtruth_estimate0/data.csv, sensor.yaml
//   <root>/mav0/body.yaml
// sensor.yaml and the csv headers follow EuRoC's files exactly, so EuRoC readers work
// unchanged. Everything is written into a staging folder next to <root>; commit() renames
// it into place, and a writer destroyed without commit() removes it, so an error never
// leaves a half-written dataset behind.
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "pllvo/camera/camera_model.h"

namespace pllvo::io {

struct EurocCamera {
  camera::CameraPtr model;  ///< pinhole-radtan or kannala-brandt (written as equidistant)
  Eigen::Isometry3d T_body_cam = Eigen::Isometry3d::Identity();  ///< EuRoC's T_BS
  double rate_hz = 20;
  std::string comment;
};

struct EurocGroundTruth {
  int64_t stamp_ns = 0;
  Eigen::Isometry3d T_world_body = Eigen::Isometry3d::Identity();
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();   ///< world frame, m/s
  Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero();  ///< rad/s
  Eigen::Vector3d accel_bias = Eigen::Vector3d::Zero();  ///< m/s^2
};

class EurocWriter {
 public:
  /// InputError when `root` exists and `overwrite` is false, or cannot be created.
  EurocWriter(std::filesystem::path root, std::vector<EurocCamera> cameras, bool overwrite = false);
  ~EurocWriter();
  EurocWriter(const EurocWriter&) = delete;
  EurocWriter& operator=(const EurocWriter&) = delete;

  /// One frame per camera (CV_8UC1 or CV_16UC1, the camera's size), saved as <ns>.png.
  void add_frame(int64_t stamp_ns, const std::vector<cv::Mat>& images);
  void add_ground_truth(const EurocGroundTruth& sample);

  /// Staging folders, for extra per-sequence or per-camera files written alongside.
  const std::filesystem::path& staging_root() const { return staging_; }
  std::filesystem::path camera_dir(size_t c) const;

  /// Flushes, then moves the staging folder to `root` (replacing it when overwriting).
  void commit();

 private:
  std::filesystem::path root_, staging_;
  std::vector<EurocCamera> cameras_;
  bool overwrite_;
  bool committed_ = false;
  std::vector<std::ofstream> frame_csv_;
  std::ofstream gt_csv_;
  int64_t last_frame_ns_ = -1, last_gt_ns_ = -1;
};

/// EuRoC's camera sensor.yaml text (%YAML:1.0, T_BS, rate_hz, resolution, intrinsics, ...).
std::string euroc_camera_yaml(const EurocCamera& camera, const std::string& comment);

}  // namespace pllvo::io
