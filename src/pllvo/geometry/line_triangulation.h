#pragma once
// Triangulation of a 3-D line segment from two views: each observed 2-D segment spans a
// plane through its camera centre; the 3-D line is the intersection of the two planes, and
// its endpoints come from intersecting the endpoint rays of the observed segments with the
// other view's plane.
#include <Eigen/Core>

#include "pllvo/common/yaml_config.h"
#include "pllvo/geometry/line3d.h"
#include "pllvo/geometry/pose.h"

namespace pllvo::geometry {

/// Which observed segment fixes the extent of the triangulated segment.
enum class LineEndpointSource {
  kFirstView,  ///< the first view's endpoints (the keyframe that detected the segment)
  kOverlap,    ///< the part of the line both views saw
  kUnion,      ///< everything either view saw
};

struct LineTriangulationConfig {
  /// Smallest angle between the two back-projected planes. Below it the intersection is
  /// ill-conditioned (a line close to an epipolar plane, or too little baseline).
  double min_plane_angle_deg = 2.0;
  /// Depth range (map units) of both endpoints in both views; max_depth <= 0: unlimited.
  double min_depth = 1e-3;
  double max_depth = 0.0;
  /// Observed segments shorter than this (normalised units, ~ pixels / focal) are rejected.
  double min_segment_length = 1e-3;
  LineEndpointSource endpoints = LineEndpointSource::kFirstView;

  void load(const ConfigNode& node);
};

enum class LineTriangulationStatus {
  kOk,
  kShortSegment,     ///< an observed segment is (nearly) a point
  kSmallPlaneAngle,  ///< back-projected planes (nearly) parallel
  kBehindCamera,     ///< an endpoint below min_depth in some view
  kTooFar,           ///< an endpoint beyond max_depth in some view
  kNoOverlap,        ///< kOverlap: the two observed extents do not overlap
};
const char* to_string(LineTriangulationStatus status);

struct TriangulatedLine {
  LineTriangulationStatus status = LineTriangulationStatus::kShortSegment;
  LineSegment3d segment_world;  ///< start/end ordered like the first view's start/end
  double plane_angle_deg = 0;
  bool ok() const { return status == LineTriangulationStatus::kOk; }
};

/// Back-projected plane (n, d), unit n, n . x + d = 0 in the world frame, of a 2-D segment seen at
/// normalised coordinates by camera T_world_cam.
Eigen::Vector4d back_projected_plane(const Pose& T_world_cam, const Eigen::Vector2d& start,
                                     const Eigen::Vector2d& end);

/// Triangulates one segment observed as (start_i, end_i), normalised coordinates, by the
/// cameras T_world_cam_i (i = 0, 1).
TriangulatedLine triangulate_line(const Pose& T_world_cam0, const Eigen::Vector2d& start0,
                                  const Eigen::Vector2d& end0, const Pose& T_world_cam1,
                                  const Eigen::Vector2d& start1, const Eigen::Vector2d& end1,
                                  const LineTriangulationConfig& config = {});

}  // namespace pllvo::geometry
