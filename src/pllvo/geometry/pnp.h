#pragma once
// Camera pose from 2-D/3-D point matches: OpenCV's RANSAC PnP on normalised coordinates
// (identity camera matrix, no distortion), then a Levenberg-Marquardt refinement on the
// inliers and a final inlier classification with the refined pose.
#include <span>
#include <vector>

#include <Eigen/Core>

#include "pllvo/common/yaml_config.h"
#include "pllvo/geometry/pose.h"

namespace pllvo::geometry {

enum class PnpMethod { kAp3p, kP3p, kEpnp, kSqpnp };

struct PnpConfig {
  /// Minimal solver inside RANSAC: AP3P (fast, 4-point samples), P3P, EPnP or SQPnP.
  PnpMethod method = PnpMethod::kAp3p;
  /// Inlier threshold on the reprojection error (pixels; converted with focal_px).
  double reprojection_threshold_px = 2.0;
  double confidence = 0.99;
  int max_iterations = 200;
  /// Fewer inliers than this is a failure (also the minimum number of matches).
  int min_inliers = 10;
  /// cv::solvePnPRefineLM on the inliers after RANSAC.
  bool refine = true;

  void load(const ConfigNode& node);
};

struct PnpResult {
  bool ok = false;
  Pose T_world_cam = Pose::Identity();
  std::vector<uint8_t> inliers;  ///< one flag per match, from the final pose
  int num_inliers = 0;
};

/// Pose of the camera observing `points_world[i]` at normalised coordinates `xy[i]`.
PnpResult solve_pnp_ransac(std::span<const Eigen::Vector3d> points_world,
                           std::span<const Eigen::Vector2d> xy, double focal_px,
                           const PnpConfig& config = {});

}  // namespace pllvo::geometry
