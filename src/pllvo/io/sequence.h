#pragma once
// One interface for every dataset: timestamped grayscale frames (mono or stereo),
// calibration and optional ground truth. Images are loaded lazily, one frame at a time.
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "pllvo/camera/camera_model.h"
#include "pllvo/io/trajectory.h"

namespace pllvo::io {

struct Frame {
  size_t index = 0;
  double timestamp = 0;  ///< seconds
  cv::Mat left;          ///< CV_8UC1, the calibration's size
  cv::Mat right;         ///< empty for mono
};

struct Calibration {
  camera::CameraPtr cam0;
  camera::CameraPtr cam1;  ///< null for mono
  Eigen::Isometry3d T_body_cam0 = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d T_body_cam1 = Eigen::Isometry3d::Identity();
  double rate_hz = 0;  ///< nominal, 0 when unknown
  bool stereo() const { return cam1 != nullptr; }
};

class Sequence {
 public:
  virtual ~Sequence() = default;
  virtual std::string format() const = 0;  ///< "euroc", "tum", "kitti", "folder"
  const std::filesystem::path& root() const { return root_; }
  const Calibration& calibration() const { return calib_; }
  size_t size() const { return stamps_.size(); }
  double timestamp(size_t i) const { return stamps_.at(i); }
  /// Loads frame i; InputError naming the image file when it is unreadable or its size
  /// differs from the calibration.
  virtual Frame frame(size_t i) const = 0;
  /// Ground truth as T_world_cam0, when the dataset has it.
  const std::optional<Trajectory>& ground_truth() const { return ground_truth_; }

 protected:
  explicit Sequence(std::filesystem::path root) : root_(std::move(root)) {}
  std::filesystem::path root_;
  Calibration calib_;
  std::vector<double> stamps_;
  std::optional<Trajectory> ground_truth_;
};

struct SequenceOptions {
  std::string format = "auto";  ///< auto | euroc | tum | kitti | folder
  /// Camera YAML for formats that ship none (TUM, folder); default: `camera.yaml` in the root.
  std::filesystem::path camera_yaml;
  bool mono = false;  ///< ignore the second camera of a stereo dataset
};

/// Opens a dataset folder, detecting the format when `options.format` is "auto".
/// Raises InputError (file and line) for anything missing or malformed, or for an
/// empty sequence or timestamps out of order.
std::unique_ptr<Sequence> open_sequence(const std::filesystem::path& root,
                                        const SequenceOptions& options = {});

}  // namespace pllvo::io
