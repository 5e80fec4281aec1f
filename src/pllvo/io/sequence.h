#pragma once
// One interface for every dataset: timestamped grayscale frames (mono or stereo),
// calibration and optional ground truth. Images are loaded lazily, one frame at a time.
// Conventions: timestamps in seconds; ground truth as T_world_cam0 (see docs/datasets.md).
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

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
  /// Depth of cam0's pixels (RGB-D): CV_32FC1, metres along the optical axis, 0 where the
  /// sensor has none; empty when the sequence has no depth or none for this frame.
  cv::Mat depth;
};

struct Calibration {
  camera::CameraPtr cam0;
  camera::CameraPtr cam1;  ///< null for mono (also when SequenceOptions::mono is set)
  /// Camera poses in the dataset's body frame (EuRoC: T_BS of each sensor.yaml; KITTI:
  /// body = cam0, cam1 at +baseline along x; mono formats: identity).
  Eigen::Isometry3d T_body_cam0 = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d T_body_cam1 = Eigen::Isometry3d::Identity();
  /// The dataset's stated frame rate (EuRoC rate_hz, camera YAML `fps`); when it states
  /// none, the mean rate of the timestamps; 0 for a single frame.
  double rate_hz = 0;
  /// Depth images (RGB-D): units per metre of their 16-bit values (TUM: 5000, pllvo's
  /// synthetic depth: 1000); 0 when the sequence has no depth (or SequenceOptions::depth is off).
  double depth_factor = 0;
  bool stereo() const { return cam1 != nullptr; }
  bool has_depth() const { return depth_factor > 0; }
  /// Distance between the two optical centres in metres (0 for mono).
  double baseline() const;
};

class Sequence {
 public:
  virtual ~Sequence() = default;
  virtual std::string format() const = 0;  ///< "euroc", "tum", "kitti", "folder"
  const std::filesystem::path& root() const { return root_; }
  const Calibration& calibration() const { return calib_; }
  size_t size() const { return stamps_.size(); }
  bool empty() const { return stamps_.empty(); }
  double timestamp(size_t i) const { return stamps_.at(i); }
  const std::vector<double>& timestamps() const { return stamps_; }
  /// Image file of frame i for camera 0 (left) or 1 (right); empty when not file-backed.
  std::filesystem::path image_path(size_t i, int cam = 0) const;
  /// Depth image of each frame when calibration().has_depth() (an empty path: none), else empty.
  const std::vector<std::filesystem::path>& depth_files() const { return depth_files_; }
  /// Loads frame i as 8-bit gray (colour and 16-bit images are converted); InputError
  /// naming the image file when it is unreadable or its size differs from the calibration.
  virtual Frame frame(size_t i) const;
  /// Ground truth as T_world_cam0, when the dataset has it.
  const std::optional<Trajectory>& ground_truth() const { return ground_truth_; }

 protected:
  explicit Sequence(std::filesystem::path root) : root_(std::move(root)) {}
  std::filesystem::path root_;
  Calibration calib_;
  std::vector<double> stamps_;
  std::vector<std::filesystem::path> left_files_;   ///< one per frame
  std::vector<std::filesystem::path> right_files_;  ///< one per frame when stereo, else empty
  /// One per frame when calib_.has_depth() (an empty path: no depth image for that frame).
  std::vector<std::filesystem::path> depth_files_;
  std::optional<Trajectory> ground_truth_;
};

struct SequenceOptions {
  std::string format = "auto";  ///< auto | euroc | tum | kitti | folder
  /// Camera YAML for formats that ship none (TUM, folder); default: `camera.yaml` in the root.
  std::filesystem::path camera_yaml;
  bool mono = false;  ///< ignore the second camera of a stereo dataset, and any depth images
  /// Read the depth images a dataset has (TUM depth.txt, EuRoC camN/depth/, an image folder's
  /// depth/): an RGB-D sequence.
  bool depth = true;
  /// TUM RGB-D: a colour frame takes the depth image nearest in time when they are at most this
  /// far apart (seconds; TUM's own association tool uses 0.02); a frame without one has no depth.
  double depth_max_dt = 0.02;
  /// EuRoC stereo: a cam0 frame is paired with the cam1 frame nearest in time when they
  /// are at most this far apart (seconds); cam0 frames without a partner are dropped
  /// with a warning. EuRoC's cameras are hardware-synchronised (identical stamps).
  double stereo_max_dt = 1e-3;
};

/// Opens a dataset folder, detecting the format when `options.format` is "auto".
/// Raises InputError (file and line) for anything missing or malformed, or for an
/// empty sequence or timestamps out of order.
std::unique_ptr<Sequence> open_sequence(const std::filesystem::path& root,
                                        const SequenceOptions& options = {});

/// The format open_sequence would pick for `root` ("euroc", "tum", "kitti", "folder");
/// InputError naming the folder when it is missing or matches no layout.
std::string detect_format(const std::filesystem::path& root);

}  // namespace pllvo::io
