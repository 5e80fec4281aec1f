#pragma once
// Metric triangulation from a rectified stereo pair (horizontal epipolar lines, right camera
// at (baseline, 0, 0) in the left camera frame, as produced by camera::StereoRectifier):
// depth = f * baseline / disparity.
#include <span>
#include <vector>

#include <Eigen/Core>

#include "pllvo/camera/camera_model.h"
#include "pllvo/common/yaml_config.h"

namespace pllvo::geometry {

struct StereoTriangulationConfig {
  /// Largest row difference between the left and right pixel (rectified images).
  double max_epipolar_error_px = 1.5;
  /// Disparity range (pixels). Small disparities give depths too uncertain to seed a metric
  /// map; max_disparity_px <= 0 means unlimited.
  double min_disparity_px = 1.0;
  double max_disparity_px = 0.0;
  /// Depth range (metres); max_depth <= 0 means unlimited.
  double min_depth = 0.1;
  double max_depth = 0.0;

  void load(const ConfigNode& node);
};

enum class StereoStatus { kOk, kEpipolar, kSmallDisparity, kLargeDisparity, kTooClose, kTooFar };
const char* to_string(StereoStatus status);

struct StereoPoint {
  StereoStatus status = StereoStatus::kSmallDisparity;
  Eigen::Vector3d p_left = Eigen::Vector3d::Zero();  ///< in the rectified left camera frame
  double disparity_px = 0;
  bool ok() const { return status == StereoStatus::kOk; }
};

/// Triangulates one match between rectified pixels of the left and right images.
StereoPoint triangulate_stereo(const Eigen::Vector2d& uv_left, const Eigen::Vector2d& uv_right,
                               const camera::PinholeIntrinsics& rectified, double baseline,
                               const StereoTriangulationConfig& config = {});

std::vector<StereoPoint> triangulate_stereo(std::span<const Eigen::Vector2d> uv_left,
                                            std::span<const Eigen::Vector2d> uv_right,
                                            const camera::PinholeIntrinsics& rectified, double baseline,
                                            const StereoTriangulationConfig& config = {});

}  // namespace pllvo::geometry
