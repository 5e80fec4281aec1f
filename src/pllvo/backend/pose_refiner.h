#pragma once
// Robust refinement of one camera pose against a fixed map: point reprojection errors plus
// line errors (distances of the projected 3-D segment endpoints to the observed 2-D lines),
// Huber or Cauchy loss, optional motion prior, optional vanishing-point
// errors of segments parallel to known directions (robust like the lines, never classified).
// Solved by Levenberg-Marquardt with iteratively reweighted normal equations on the 6-DoF
// pose (hand-written: a per-frame solve of ~10 small iterations, where building a Ceres
// problem would cost more than solving).
// Several rounds re-classify outliers and leave them out of the next round (ORB-SLAM style).
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "pllvo/backend/robust_loss.h"
#include "pllvo/common/yaml_config.h"
#include "pllvo/geometry/pose.h"

namespace pllvo::backend {

using geometry::Pose;

struct PoseRefinerConfig {
  RobustLoss point_loss{LossType::kHuber, 2.0};
  RobustLoss line_loss{LossType::kHuber, 2.0};
  /// Multiplies the line residuals (pixels) relative to the point residuals.
  double line_weight = 1.0;
  /// Rounds of (optimise, classify outliers); later rounds leave the outliers out.
  int rounds = 2;
  int iterations_per_round = 10;
  /// Residual norm (pixels; for lines the norm of the two endpoint distances) above which an
  /// observation is an outlier.
  double point_outlier_threshold_px = 3.0;
  double line_outlier_threshold_px = 3.0;
  /// Inliers (points + lines) needed for the result to be usable.
  int min_inliers = 10;
  /// Motion prior: used when the problem carries a predicted pose. Sigmas of the camera
  /// position (map units) and orientation (degrees) around the prediction.
  bool use_motion_prior = true;
  double prior_sigma_position = 0.05;
  double prior_sigma_rotation_deg = 2.0;

  void load(const ConfigNode& node);
};

struct PosePointObservation {
  Eigen::Vector3d p_world;
  Eigen::Vector2d xy;  ///< normalised image coordinates in camera `camera`
  int camera = 0;
  /// Scales the residual (and so the outlier test): below 1 for a point whose map position
  /// is uncertain.
  double weight = 1.0;
};

struct PoseLineObservation {
  Eigen::Vector3d start_world, end_world;  ///< the map segment
  Eigen::Vector3d line;                    ///< observed 2-D line, normalised (a^2 + b^2 = 1)
  int camera = 0;
};

/// A segment (camera 0) parallel to a known 3-D direction: its distance from pointing at the
/// direction's vanishing point constrains the rotation alone (geometry::vanishing_residual).
struct PoseDirectionObservation {
  Eigen::Vector3d direction_world;
  Eigen::Vector2d start, end;  ///< normalised image coordinates
};

struct PoseRefinementProblem {
  Pose T_world_cam = Pose::Identity();  ///< initial guess (camera 0)
  std::vector<PosePointObservation> points;
  std::vector<PoseLineObservation> lines;
  double focal_px = 1.0;  ///< pixels per normalised unit (geometry::pixel_scale)
  std::optional<Pose> predicted_T_world_cam;  ///< motion-model prediction for the prior
  std::vector<Pose> T_cam_cam0;                ///< rig extrinsics by camera index; empty: mono
  /// Segments parallel to known directions; robust with the line loss, never classified.
  std::vector<PoseDirectionObservation> directions;
  double direction_weight = 0;  ///< multiplies their residuals (pixels); 0: unused
};

struct PoseRefinementResult {
  bool ok = false;  ///< enough inliers and a finite pose
  Pose T_world_cam = Pose::Identity();
  std::vector<uint8_t> point_inliers, line_inliers;
  int num_point_inliers = 0, num_line_inliers = 0;
  double initial_rms_px = 0, final_rms_px = 0;  ///< over the final inliers
  int iterations = 0;
};

class PoseRefiner {
 public:
  explicit PoseRefiner(PoseRefinerConfig config = {}) : config_(config) {}
  const PoseRefinerConfig& config() const { return config_; }

  PoseRefinementResult refine(const PoseRefinementProblem& problem) const;

 private:
  PoseRefinerConfig config_;
};

}  // namespace pllvo::backend
