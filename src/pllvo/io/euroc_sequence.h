#pragma once
// EuRoC MAV / ASL dataset layout:
//   mav0/cam0/data.csv            `#timestamp [ns],filename`, images in mav0/cam0/data/
//   mav0/cam0/sensor.yaml         T_BS, resolution, intrinsics, distortion, rate_hz
//   mav0/cam1/...                 the right camera (optional)
//   mav0/state_groundtruth_estimate0/data.csv   body poses (optional)
#include <filesystem>

#include <Eigen/Geometry>

#include "pllvo/io/sequence.h"

namespace pllvo::io {

/// One camera's sensor.yaml. EuRoC's files start with OpenCV's `%YAML:1.0`, which yaml-cpp
/// rejects; that directive is accepted here.
struct EurocCameraSensor {
  camera::CameraPtr camera;
  Eigen::Isometry3d T_body_cam = Eigen::Isometry3d::Identity();  ///< T_BS, rotation re-orthonormalised
  double rate_hz = 0;                                            ///< 0 when the file has none
  /// Units per metre of the camera's depth images (camN/depth/), the optional key
  /// `depth_factor`; 0 when absent (pllvo's synthetic sequences write millimetres: 1000).
  double depth_factor = 0;
};
/// InputError naming the file and the key (or the line, for malformed YAML).
EurocCameraSensor read_euroc_sensor_yaml(const std::filesystem::path& file);

/// `root` is the folder that holds mav0/, or mav0/ itself. Timestamps are double(ns) / 1e9
/// (evo's conversion). Stereo when mav0/cam1/ exists and options.mono is not set: each cam0
/// frame is paired with the nearest cam1 frame within options.stereo_max_dt, unpaired cam0
/// frames are dropped with a warning, and no pair at all is an InputError. Ground truth:
/// state_groundtruth_estimate0/data.csv (T_world_body) times cam0's T_BS = T_world_cam0.
class EurocSequence final : public Sequence {
 public:
  EurocSequence(const std::filesystem::path& root, const SequenceOptions& options = {});
  std::string format() const override { return "euroc"; }
};

}  // namespace pllvo::io
