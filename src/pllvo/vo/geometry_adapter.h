#pragma once
// The pipeline's calls into geometry/ and backend/, on the pipeline's own types: pixels of
// the ideal pinhole working images in, normalised coordinates (what those modules use) inside.
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "pllvo/backend/backend_config.h"
#include "pllvo/geometry/geometry_config.h"
#include "pllvo/geometry/pose.h"
#include "pllvo/vo/map.h"

namespace pllvo::vo {

/// Ideal pinhole camera of the images the pipeline works on (undistorted or rectified).
struct Pinhole {
  double fx = 0, fy = 0, cx = 0, cy = 0;
  int width = 0, height = 0;
  /// False behind the camera (z <= 1e-6).
  bool project(const Eigen::Vector3d& p_cam, Eigen::Vector2d& px) const;
  Eigen::Vector2d normalised(const Eigen::Vector2d& px) const { return {(px.x() - cx) / fx, (px.y() - cy) / fy}; }
  Eigen::Vector2d pixel(const Eigen::Vector2d& xy) const { return {fx * xy.x() + cx, fy * xy.y() + cy}; }
  double focal() const { return 0.5 * (fx + fy); }  ///< pixels per normalised unit
  bool inside(const Eigen::Vector2d& px, double border = 0) const;
};

/// A 3-D line (world endpoints) observed as a 2-D segment (pixels) in the frame.
struct LineMeasurement {
  Eigen::Vector3d start_world, end_world;
  Segment2d observed;
};

struct PoseEstimate {
  bool ok = false;
  geometry::Pose T_world_cam = geometry::Pose::Identity();
  std::vector<unsigned char> point_inliers;  ///< per point given
  std::vector<unsigned char> line_inliers;   ///< per line given
  int num_point_inliers = 0, num_line_inliers = 0;
  bool from_pnp = false;  ///< false: refined from the prediction alone (PnP failed)
};

/// Terms of a frame's pose refinement beside the points and lines: directions.
struct PoseExtras {
  std::vector<backend::PoseDirectionObservation> directions;  ///< segments parallel to known directions
  double direction_weight = 0;                               ///< 0: the directions are not used
};

/// Pose of a frame: PnP + RANSAC on the points, then the robust refinement with points,
/// lines and (when `predicted` is given) the motion prior. Without a PnP solution the
/// refinement starts at the prediction, so lines can carry a frame with few points.
/// `extras` add monocular terms to the refinement.
PoseEstimate estimate_pose(const Pinhole& cam, const std::vector<Eigen::Vector3d>& points_world,
                           const std::vector<Eigen::Vector2d>& pixels, const std::vector<LineMeasurement>& lines,
                           const std::optional<geometry::Pose>& predicted_T_world_cam,
                           const geometry::GeometryConfig& geometry, const backend::BackendConfig& backend,
                           const PoseExtras& extras = {});

/// PnP + RANSAC alone (frames seen during monocular initialisation).
PoseEstimate estimate_pose_pnp(const Pinhole& cam, const std::vector<Eigen::Vector3d>& points_world,
                               const std::vector<Eigen::Vector2d>& pixels, const geometry::PnpConfig& config);

struct TwoViewInit {
  bool ok = false;
  std::string model;  ///< "essential" | "homography"
  std::string failure;
  geometry::Pose T_cam1_cam0 = geometry::Pose::Identity();  ///< |t| = 1
  std::vector<std::optional<Eigen::Vector3d>> points_cam0;  ///< per correspondence
  double median_parallax_deg = 0;
  int num_inliers = 0;       ///< matches that fit the chosen model
  int num_triangulated = 0;  ///< of them, triangulated by the best decomposition
  double direction_sigma_deg = std::numeric_limits<double>::infinity();  ///< of the translation direction (inf: not measured)
  double residual_rms_px = 0;      ///< the inliers' Sampson errors
  int vanishing_pairs = 0;         ///< directions seen in both views that held the rotation
};

/// Monocular initialisation from pixel correspondences (E vs H, chosen by score); directions
/// seen in both views (camera frames) hold the rotation when config.vanishing_sigma_deg > 0.
TwoViewInit initialize_two_view(const Pinhole& cam, const std::vector<Eigen::Vector2d>& px0,
                                const std::vector<Eigen::Vector2d>& px1, const geometry::TwoViewConfig& config,
                                const geometry::ViewDirections* directions = nullptr);

/// Point from views with known poses (parallax, depth and reprojection checks).
std::optional<Eigen::Vector3d> triangulate_point(const Pinhole& cam, const std::vector<geometry::Pose>& T_world_cam,
                                                 const std::vector<Eigen::Vector2d>& pixels,
                                                 const geometry::PointTriangulationConfig& config);

/// Distances (px) between the projections of `points_world` at `T_world_cam` and `pixels`; a
/// point behind the camera counts as 1e9.
std::vector<double> reprojection_errors_px(const Pinhole& cam, const std::vector<Eigen::Vector3d>& points_world,
                                           const std::vector<Eigen::Vector2d>& pixels,
                                           const geometry::Pose& T_world_cam);

/// Their median; 0 when there are none.
double median_reprojection_px(const Pinhole& cam, const std::vector<Eigen::Vector3d>& points_world,
                              const std::vector<Eigen::Vector2d>& pixels, const geometry::Pose& T_world_cam);

/// A keyframe's bundle adjustment moved its pose from `T_world_added` to `T_world_adjusted`, and
/// its points with it. When those points, tracked at `pixels` now, miss the current pose
/// `T_world_current` by more than `gate_px` in the median, the adjustment has moved its window as a
/// whole: returns the current pose moved the same way (the motion since the keyframe kept), if
/// the points then project closer. Otherwise nullopt.
std::optional<geometry::Pose> follow_keyframe_adjustment(const Pinhole& cam,
                                                         const std::vector<Eigen::Vector3d>& points_world,
                                                         const std::vector<Eigen::Vector2d>& pixels,
                                                         const geometry::Pose& T_world_current,
                                                         const geometry::Pose& T_world_added,
                                                         const geometry::Pose& T_world_adjusted, double gate_px);

/// When most of `points_world`, tracked at `pixels`, miss `T_world_current` by more than
/// `gate_px`: their pose by PnP (`config`), if at least twice as many of them lie within the gate
/// there and at least one does. Otherwise nullopt.
std::optional<geometry::Pose> pose_of_merged_tracks(const Pinhole& cam, const std::vector<Eigen::Vector3d>& points_world,
                                                    const std::vector<Eigen::Vector2d>& pixels,
                                                    const geometry::Pose& T_world_current, double gate_px,
                                                    const geometry::PnpConfig& config);

/// Pose of the right rectified camera in the left one: +baseline along the left camera's x axis.
geometry::Pose T_left_right(double baseline);

/// Point in the left rectified camera from a left-right match.
std::optional<Eigen::Vector3d> triangulate_stereo(const Pinhole& cam, double baseline, const Eigen::Vector2d& left,
                                                  const Eigen::Vector2d& right,
                                                  const geometry::StereoTriangulationConfig& config);

struct WindowBaResult {
  bool ran = false;
  int point_outliers = 0, line_outliers = 0;
  double final_rms_px = 0;
  double solve_ms = 0;
  double stereo_offset_px = 0;  ///< the rectified pair's horizontal offset after the solve
};

/// Sliding-window bundle adjustment: `window` (keyframe ids, oldest first) plus, fixed, up to
/// `max_anchors` older keyframes of the same segment that see the window's points. Reads the
/// map under its lock, solves without it (only the worker writes the map, so nothing changes
/// meanwhile), then writes poses, points and lines back and unlinks outlier observations.
/// `baseline` > 0: keyframes' right-image points join as observations of the rectified
/// right camera (metric scale in the window), their x shifted by `stereo_offset_px` (the
/// rectified pair's horizontal offset, estimated when config.stereo_offset_sigma_px > 0 and
/// returned). `direction_weight` > 0: the keyframes' segments parallel to known directions
/// hold their rotations.
WindowBaResult bundle_adjust_window(Map& map, const Pinhole& cam, double baseline, const std::vector<Id>& window,
                                    int max_anchors, const backend::BundleAdjustmentConfig& config,
                                    double direction_weight = 0, double stereo_offset_px = 0);

}  // namespace pllvo::vo
