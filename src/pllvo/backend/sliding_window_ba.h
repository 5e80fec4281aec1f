#pragma once
// Sliding-window bundle adjustment (Ceres) over keyframe poses, 3-D points and 3-D line
// segments, with point reprojection and line residuals (see ba_costs.h), robust losses, and
// the older keyframes held fixed.
//
// Which keyframes move: keyframes are given oldest first. The newest `window_size` ones are
// optimised, except those flagged `fixed` by the caller and the oldest `num_fixed_oldest` of
// the whole list, which fix the gauge (one keyframe fixes position and orientation; a
// monocular map also has a free scale, which two fixed keyframes pin). Older keyframes passed
// in (e.g. ones that also see the window's landmarks) constrain the solution but stay put.
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "pllvo/backend/robust_loss.h"
#include "pllvo/common/yaml_config.h"
#include "pllvo/geometry/line3d.h"
#include "pllvo/geometry/pose.h"

namespace pllvo::backend {

using geometry::Pose;

enum class BaJacobians { kAnalytic, kAutodiff };
enum class BaLinearSolver { kDenseSchur, kSparseSchur };

struct BundleAdjustmentConfig {
  int window_size = 10;      ///< newest keyframes optimised
  int num_fixed_oldest = 1;  ///< oldest keyframes always fixed (gauge); 2 for monocular scale
  /// Monocular scale held by one distance instead of a second fixed pose: while fewer than two
  /// keyframes are fixed, the first free one keeps its distance to the first fixed one and is
  /// otherwise free (a second fixed pose also freezes the rotation and the translation
  /// direction of a two-view start, errors of a degree and tens of degrees at 1 degree of
  /// parallax). Use with num_fixed_oldest = 1.
  bool distance_gauge = false;
  /// Landmarks with fewer observations in the problem are held fixed: one view does not
  /// constrain a point's depth or a line's position.
  int min_point_observations = 2;
  int min_line_observations = 2;
  RobustLoss point_loss{LossType::kHuber, 2.0};
  RobustLoss line_loss{LossType::kHuber, 2.0};
  double line_weight = 1.0;  ///< multiplies the line residuals relative to the points
  int max_iterations = 10;
  /// After the first solve, drop the observations classified as outliers and solve again.
  bool second_pass = true;
  int second_pass_iterations = 5;
  /// Residual norm (pixels) above which an observation is an outlier.
  double point_outlier_threshold_px = 3.0;
  double line_outlier_threshold_px = 3.0;
  double function_tolerance = 1e-6;
  double max_solver_time_s = 0.0;  ///< per solve; <= 0: no limit
  int num_threads = 1;
  /// Stereo: the rectified pair's horizontal offset (BaProblem::stereo_offset_px) is estimated
  /// with a zero-mean prior of this standard deviation (pixels); 0: held at its given value.
  /// A rectification whose right principal point is off by a pixel biases every stereo depth
  /// by one pixel of disparity: 17 % at the 4-8 px of a highway's far field, where a 1 px shift
  /// of the right images brings KITTI 01's stereo scale from 1.19 to 1.04 (docs/vo.md). Motion
  /// makes it observable (near and far points' parallax against their disparities); without
  /// motion the prior keeps it.
  double stereo_offset_sigma_px = 1.0;
  BaJacobians jacobians = BaJacobians::kAnalytic;
  BaLinearSolver linear_solver = BaLinearSolver::kDenseSchur;

  void load(const ConfigNode& node);
};

struct BaKeyframe {
  Pose T_world_cam = Pose::Identity();  ///< camera 0 of the keyframe
  bool fixed = false;
};

struct BaPoint {
  Eigen::Vector3d p_world = Eigen::Vector3d::Zero();
  bool fixed = false;
};

struct BaLine {
  geometry::LineSegment3d segment_world;
  bool fixed = false;
};

struct BaPointObservation {
  int keyframe = 0, point = 0, camera = 0;
  Eigen::Vector2d xy = Eigen::Vector2d::Zero();  ///< normalised image coordinates
};

struct BaLineObservation {
  int keyframe = 0, line = 0, camera = 0;
  Eigen::Vector3d line_coeffs = Eigen::Vector3d::Zero();  ///< normalised 2-D line, a^2 + b^2 = 1
};

/// A segment seen by a keyframe (camera 0) parallel to a known world direction: its
/// vanishing-point error (geometry::vanishing_residual) holds the keyframe's rotation.
struct BaDirectionObservation {
  int keyframe = 0;
  Eigen::Vector3d direction_world = Eigen::Vector3d::UnitZ();
  Eigen::Vector2d start = Eigen::Vector2d::Zero(), end = Eigen::Vector2d::Zero();  ///< normalised
};

/// Everything one bundle adjustment sees; optimize() writes the free values back in place.
struct BaProblem {
  std::vector<BaKeyframe> keyframes;  ///< oldest first
  std::vector<BaPoint> points;
  std::vector<BaLine> lines;
  std::vector<BaPointObservation> point_observations;
  std::vector<BaLineObservation> line_observations;
  /// With the line loss, never classified as outliers; weighted by direction_weight (pixels).
  std::vector<BaDirectionObservation> direction_observations;
  double direction_weight = 0;  ///< 0: the directions are not used
  std::vector<Pose> T_cam_cam0;  ///< rig extrinsics by camera index; empty: mono
  /// Pixels added to the horizontal residual of every camera > 0 observation: the true
  /// disparity is the measured one plus this. Estimated in place (stereo_offset_sigma_px).
  double stereo_offset_px = 0;
  double focal_px = 1.0;         ///< pixels per normalised unit (geometry::pixel_scale)
};

struct BaSummary {
  bool ok = false;  ///< Ceres produced a usable solution
  int iterations = 0;
  double initial_cost = 0, final_cost = 0;  ///< Ceres costs (robustified), first and last solve
  double initial_rms_px = 0, final_rms_px = 0;  ///< residual norms over the final inliers
  std::vector<uint8_t> point_outliers, line_outliers;  ///< per observation, after the solve
  int num_point_outliers = 0, num_line_outliers = 0;
  int num_free_keyframes = 0, num_free_points = 0, num_free_lines = 0;
  double solve_time_s = 0;
  std::string report;  ///< Ceres' brief report of the last solve
};

class SlidingWindowBA {
 public:
  explicit SlidingWindowBA(BundleAdjustmentConfig config = {}) : config_(config) {}
  const BundleAdjustmentConfig& config() const { return config_; }

  /// Optimises `problem` in place. InternalError when an observation names a keyframe,
  /// landmark or camera that does not exist.
  BaSummary optimize(BaProblem& problem) const;

  /// Whether keyframe i of n (oldest first, caller's flag `fixed`) is held fixed.
  bool keyframe_fixed(int i, int n, bool fixed) const;

  /// With distance_gauge: the keyframes (reference: the first fixed, moving: the first free one
  /// with observations) whose distance is held, when fewer than two keyframes are fixed;
  /// {-1, -1} otherwise. Validated observations expected (optimize() checks them first).
  std::pair<int, int> distance_gauge_pair(const BaProblem& problem) const;

 private:
  BundleAdjustmentConfig config_;
};

}  // namespace pllvo::backend
