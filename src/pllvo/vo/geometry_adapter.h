#pragma once
// What the pipeline needs from geometry/ and backend/, as a few functions on the pipeline's
// own types. The bodies call those modules; until they land, thin OpenCV calls stand in
// (marked INTERIM), so the pipeline runs end to end from the start.
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "pllvo/geometry/pose.h"
#include "pllvo/vo/map.h"
#include "pllvo/vo/vo_config.h"

namespace pllvo::vo {

/// Ideal pinhole camera of the images the pipeline works on (undistorted or rectified).
struct Pinhole {
  double fx = 0, fy = 0, cx = 0, cy = 0;
  int width = 0, height = 0;
  Eigen::Matrix3d K() const;
  /// False behind the camera (z <= 1e-6).
  bool project(const Eigen::Vector3d& p_cam, Eigen::Vector2d& px) const;
  /// Normalised ray (x, y, 1) through a pixel.
  Eigen::Vector3d ray(const Eigen::Vector2d& px) const;
  bool inside(const Eigen::Vector2d& px, double border = 0) const;
};

struct PoseEstimate {
  bool ok = false;
  geometry::Pose T_cam_world = geometry::Pose::Identity();
  std::vector<unsigned char> inliers;  ///< per point
  int num_inliers = 0;
};

/// A 3-D line (world endpoints) observed as a 2-D segment in the frame.
struct LineMeasurement {
  Eigen::Vector3d p_world, q_world;
  Segment2d observed;
};

/// PnP + RANSAC; `guess` (the motion prior) seeds it when given.
PoseEstimate estimate_pose_ransac(const Pinhole& cam, const std::vector<Eigen::Vector3d>& points_world,
                                  const std::vector<Eigen::Vector2d>& pixels, const geometry::Pose* guess,
                                  const PoseConfig& config);

/// Robust refinement minimising point reprojection error plus the line error (distance of
/// projected 3-D endpoints to the observed 2-D line), over the points marked in `use`.
/// Returns the refined pose and the points whose residual is below the RANSAC threshold.
PoseEstimate refine_pose(const Pinhole& cam, const geometry::Pose& T_cam_world,
                         const std::vector<Eigen::Vector3d>& points_world, const std::vector<Eigen::Vector2d>& pixels,
                         const std::vector<unsigned char>& use, const std::vector<LineMeasurement>& lines,
                         const PoseConfig& config);

struct TwoViewResult {
  bool ok = false;
  std::string model;  ///< "essential" or "homography"
  geometry::Pose T_1_0 = geometry::Pose::Identity();  ///< second camera from first; |t| = 1
  std::vector<Eigen::Vector3d> points_0;              ///< triangulated, first camera frame
  std::vector<unsigned char> valid;                   ///< per correspondence
  double median_parallax_deg = 0;
};

/// Monocular initialisation from pixel correspondences: essential matrix vs homography,
/// chosen by score, then triangulation with parallax and depth checks.
TwoViewResult initialize_two_view(const Pinhole& cam, const std::vector<Eigen::Vector2d>& px0,
                                  const std::vector<Eigen::Vector2d>& px1, const InitConfig& config);

/// Point from two views with known poses; nullopt when the rays are too parallel, the point
/// lies behind a camera or outside the depth range, or it reprojects badly.
std::optional<Eigen::Vector3d> triangulate_point(const Pinhole& cam, const geometry::Pose& T_world_c0,
                                                 const geometry::Pose& T_world_c1, const Eigen::Vector2d& px0,
                                                 const Eigen::Vector2d& px1, const MappingConfig& config);

/// Point in the left rectified camera from a left-right match (disparity along x).
std::optional<Eigen::Vector3d> triangulate_stereo(const Pinhole& cam, double baseline, const Eigen::Vector2d& left,
                                                  const Eigen::Vector2d& right, double min_depth, double max_depth);

/// Sliding-window bundle adjustment over `window` (oldest first); the first `fixed` keyframes
/// stay fixed. Updates poses, points and lines in `map`; returns the number of observations
/// rejected as outliers (their links are removed).
int bundle_adjust_window(MapData& map, const Pinhole& cam, const std::vector<Id>& window, int fixed,
                         const MappingConfig& config);

}  // namespace pllvo::vo
