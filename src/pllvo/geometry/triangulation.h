#pragma once
// Triangulation of a 3-D point from two or more calibrated views: linear (DLT) solution,
// Gauss-Newton refinement of the reprojection error, then the checks that decide whether
// the point may enter the map (parallax, depth, reprojection error in every view).
#include <span>
#include <string>

#include <Eigen/Core>

#include "pllvo/common/yaml_config.h"
#include "pllvo/geometry/pose.h"

namespace pllvo::geometry {

struct PointTriangulationConfig {
  /// Largest angle between any two observation rays must reach this; below it the depth is
  /// too uncertain (1 deg is ORB-SLAM's choice for map points).
  double min_parallax_deg = 1.0;
  /// Reprojection error allowed in every view after refinement (pixels).
  double max_reprojection_error_px = 2.0;
  /// Depth range (map units) in every view; max_depth <= 0 means unlimited.
  double min_depth = 1e-3;
  double max_depth = 0.0;
  /// Gauss-Newton iterations on the reprojection error after the DLT; 0 keeps the DLT point.
  int refine_iterations = 5;

  void load(const ConfigNode& node);
};

enum class TriangulationStatus {
  kOk,
  kTooFewViews,   ///< fewer than two observations, or sizes differ
  kLowParallax,   ///< rays too close to parallel
  kDegenerate,    ///< the linear system has no finite solution
  kBehindCamera,  ///< depth below min_depth in some view
  kTooFar,        ///< depth beyond max_depth in some view
  kLargeError,    ///< reprojection error above the threshold in some view
};
const char* to_string(TriangulationStatus status);

struct TriangulatedPoint {
  TriangulationStatus status = TriangulationStatus::kTooFewViews;
  Eigen::Vector3d p_world = Eigen::Vector3d::Zero();
  double parallax_deg = 0;   ///< largest angle between two observation rays
  double max_error_px = 0;   ///< largest reprojection error over the views
  bool ok() const { return status == TriangulationStatus::kOk; }
};

/// Triangulates one point seen at normalised coordinates `xy[i]` by cameras `T_world_cam[i]`.
/// `focal_px` (see pixel_scale) converts the pixel threshold to normalised units.
TriangulatedPoint triangulate_point(std::span<const Pose> T_world_cam,
                                    std::span<const Eigen::Vector2d> xy, double focal_px,
                                    const PointTriangulationConfig& config = {});

/// Linear (DLT) triangulation from camera-from-world poses; false when the solution is at
/// infinity or not finite.
bool triangulate_linear(std::span<const Pose> T_cam_world, std::span<const Eigen::Vector2d> xy,
                        Eigen::Vector3d& p_world);

/// Gauss-Newton on the summed squared normalised reprojection error, starting from
/// `p_world`; stops early when a step stops helping or moves the point behind a camera.
void refine_point(std::span<const Pose> T_cam_world, std::span<const Eigen::Vector2d> xy,
                  int iterations, Eigen::Vector3d& p_world);

/// Largest angle (degrees) between the world-frame rays of the observations.
double max_parallax_deg(std::span<const Pose> T_world_cam, std::span<const Eigen::Vector2d> xy);

}  // namespace pllvo::geometry
