#pragma once
// Monocular initialisation from two views: an essential matrix and a homography are fitted
// with RANSAC (OpenCV), scored ORB-SLAM style on all matches by their symmetric transfer
// errors, the better model is decomposed, and the decomposition whose triangulated points
// pass cheirality and reprojection checks (clearly ahead of the other candidates) wins.
// The translation has unit length: the map scale is arbitrary. Optionally the motion is
// searched over directions (a short baseline's cost has more than one valley) and refused when
// its direction is too uncertain; both off by default (docs/vo.md). Directions seen
// in both views (vanishing points) can hold the rotation, so that the translation has none to
// trade for; off by default.
#include <limits>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "pllvo/common/yaml_config.h"
#include "pllvo/geometry/pose.h"

namespace pllvo::geometry {

struct TwoViewConfig {
  /// Standard deviation of the feature position (pixels): the score thresholds are the
  /// chi-square 95% bounds in units of sigma^2 (3.84 for the 1-D epipolar distance, 5.99
  /// for the 2-D homography transfer).
  double sigma_px = 1.0;
  /// RANSAC inlier threshold of the OpenCV fits (pixels).
  double ransac_threshold_px = 1.5;
  double ransac_confidence = 0.999;
  int ransac_max_iterations = 1000;
  /// The homography is chosen when S_H / (S_H + S_E) exceeds this (ORB-SLAM: 0.45).
  double homography_ratio = 0.45;
  /// A point is consistent with a candidate motion when it lies in front of both cameras
  /// and reprojects within this error (pixels) in both views.
  double max_reprojection_error_px = 2.0;
  /// Points with a smaller parallax are not returned as triangulated (depth too uncertain).
  double min_point_parallax_deg = 1.0;
  /// Median parallax of the consistent points must reach this, else the baseline is too
  /// short to initialise.
  double min_median_parallax_deg = 1.0;
  /// Minimum number of triangulated points, and the fraction of model inliers that the
  /// winning candidate must explain (35 with vo's init.min_points: docs/vo.md).
  int min_triangulated = 35;
  double min_good_fraction = 0.9;
  /// Rejected as ambiguous when another candidate explains more than this fraction of the
  /// winner's consistent points.
  double max_ambiguity = 0.7;
  /// Rejected while the translation direction's standard deviation
  /// (`translation_direction_uncertainty`) exceeds this many degrees (0: off).
  double max_direction_sigma_deg = 0.0;
  /// The motion is also refined from this many translation directions spread over the sphere
  /// and the best-scoring one kept: over a short baseline the RANSAC winner may lie in a wrong
  /// valley of the cost (0: refined from the winner only).
  int direction_search_starts = 0;
  /// Vanishing directions seen in both views (`ViewDirections`) hold the rotation with this
  /// standard deviation (degrees): the translation's direction then follows from the matches
  /// alone, without the rotation it trades for over a short baseline (0: not used).
  double vanishing_sigma_deg = 0.0;
  /// A direction of view 0 and one of view 1 are the same when the RANSAC winner's rotation
  /// maps one within this angle (degrees) of the other.
  double vanishing_gate_deg = 5.0;

  void load(const ConfigNode& node);
};

/// Unit 3-D directions found in each view alone (camera frames; d and -d are one direction),
/// e.g. the vanishing points of a room's edges.
struct ViewDirections {
  std::vector<Eigen::Vector3d> cam0, cam1;
};

/// How well a two-view motion fixes its translation's direction.
struct DirectionUncertainty {
  /// Standard deviation (degrees) of the direction along its worse axis; infinite when the
  /// matches leave it undetermined.
  double sigma_deg = std::numeric_limits<double>::infinity();
  double residual_rms_px = 0;  ///< the inliers' Sampson errors, taken as their noise
  int num_matches = 0;
};

enum class TwoViewModel { kNone, kEssential, kHomography };
const char* to_string(TwoViewModel model);

struct TwoViewResult {
  bool ok = false;
  TwoViewModel model = TwoViewModel::kNone;
  Pose T_cam1_cam0 = Pose::Identity();  ///< |translation| = 1
  std::vector<uint8_t> inliers;         ///< matches consistent with the chosen model's score
  std::vector<Eigen::Vector3d> points_cam0;  ///< per match; valid where `triangulated`
  std::vector<uint8_t> triangulated;
  int num_triangulated = 0;  ///< by the best decomposition; also set when ok is false (why it failed)
  double median_parallax_deg = 0;
  double score_essential = 0, score_homography = 0;
  DirectionUncertainty direction;  ///< of the final motion (ok), or of the RANSAC winner
  int vanishing_pairs = 0;  ///< directions seen in both views that held the rotation
  std::string failure;  ///< why ok is false
};

/// Relative pose of the second view from matches at normalised coordinates xy0[i] <-> xy1[i];
/// with `directions` (and config.vanishing_sigma_deg > 0) those seen in both views hold the
/// rotation.
TwoViewResult initialise_two_view(std::span<const Eigen::Vector2d> xy0,
                                  std::span<const Eigen::Vector2d> xy1, double focal_px,
                                  const TwoViewConfig& config = {}, const ViewDirections* directions = nullptr);

/// The motion's information from the inliers' Sampson errors (each match's point eliminated to
/// first order), with the errors' own rms as noise, inverted: the direction's standard
/// deviation with the rotation free. Over a short baseline rotation and sideways translation
/// nearly trade for each other (the bas-relief ambiguity), so a direction can be tens of
/// degrees off while every match fits; the median parallax does not show that, this does.
DirectionUncertainty translation_direction_uncertainty(const Pose& T_cam1_cam0, std::span<const Eigen::Vector2d> xy0,
                                                       std::span<const Eigen::Vector2d> xy1,
                                                       const std::vector<uint8_t>& inliers, double focal_px);

/// Motion between two consecutive frames of a monocular camera, for tracking through a stretch
/// where the map has no points in view (a fast turn): translation of unit length, its scale to
/// be taken from elsewhere (the last velocity).
struct RelativeMotion {
  bool ok = false;
  Pose T_cam1_cam0 = Pose::Identity();  ///< |translation| = 1
  std::vector<uint8_t> inliers;         ///< matches within the essential matrix's score bound
  int num_inliers = 0;
  double rotation_from_expected_deg = 0, translation_from_expected_deg = 0;
  bool translation_kept = false;  ///< the translation is the expected one (see keep_expected_translation)
  std::string failure;  ///< why ok is false
};

struct RelativeMotionLimits {
  int min_inliers = 20;
  /// The chosen motion may differ from the expected one (constant velocity) by at most this
  /// much: over one frame's baseline a wrong fit is more likely than such a change of motion.
  double max_rotation_change_deg = 5.0;
  double max_translation_change_deg = 45.0;
  /// Over one frame's baseline the translation's direction is weakly determined: the
  /// refinement pulls it towards the expected one with this standard deviation (0: no pull).
  double translation_prior_sigma_deg = 15.0;
  /// When the measured direction is too far from the expected one, fit the rotation alone with
  /// the expected direction, instead of failing.
  bool keep_expected_translation = true;
};

/// The essential matrix (RANSAC, config's thresholds) between xy0[i] <-> xy1[i], the
/// decomposition that puts most informative points in front of both views, refined on its
/// inliers' Sampson errors with the expected translation direction as a prior; checked against
/// the expected motion.
RelativeMotion estimate_relative_motion(std::span<const Eigen::Vector2d> xy0,
                                        std::span<const Eigen::Vector2d> xy1, double focal_px,
                                        const Pose& expected_T_cam1_cam0, const RelativeMotionLimits& limits,
                                        const TwoViewConfig& config = {});

/// ORB-SLAM's model score: sum over matches and both directions of (5.99 - d^2 / sigma^2)
/// where d^2 / sigma^2 is below the model's chi-square threshold, 0 elsewhere; `inliers`
/// flags matches within the threshold in both directions. d is in pixels (normalised * focal).
double score_essential(const Eigen::Matrix3d& E, std::span<const Eigen::Vector2d> xy0,
                       std::span<const Eigen::Vector2d> xy1, double focal_px, double sigma_px,
                       std::vector<uint8_t>& inliers);
double score_homography(const Eigen::Matrix3d& H_1_0, std::span<const Eigen::Vector2d> xy0,
                        std::span<const Eigen::Vector2d> xy1, double focal_px, double sigma_px,
                        std::vector<uint8_t>& inliers);

}  // namespace pllvo::geometry
