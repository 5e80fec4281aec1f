#include "pllvo/geometry/line_triangulation.h"

#include <algorithm>
#include <cmath>

#include "pllvo/geometry/config_choice.h"
#include "pllvo/geometry/reprojection.h"

namespace pllvo::geometry {

namespace {
constexpr double kRadToDeg = 180.0 / M_PI;

const Choices<LineEndpointSource> kEndpointChoices = {{"first_view", LineEndpointSource::kFirstView},
                                                      {"overlap", LineEndpointSource::kOverlap},
                                                      {"union", LineEndpointSource::kUnion}};

/// Intersection of the ray through normalised point xy of camera T_world_cam with a plane;
/// returns the depth along the camera's z axis (negative or non-finite when it misses).
double ray_plane_depth(const Pose& T_world_cam, const Eigen::Vector2d& xy, const Eigen::Vector4d& plane,
                       Eigen::Vector3d& x_world) {
  const Eigen::Vector3d c = T_world_cam.translation();
  const Eigen::Vector3d r = T_world_cam.linear() * Eigen::Vector3d(xy.x(), xy.y(), 1.0);
  const double denom = plane.head<3>().dot(r);
  const double depth = -(plane.head<3>().dot(c) + plane.w()) / denom;
  x_world = c + depth * r;
  return depth;
}

LineTriangulationStatus check_depth(const Pose& T_cam_world, const Eigen::Vector3d& x,
                                    const LineTriangulationConfig& config) {
  const double z = (T_cam_world * x).z();
  if (!(z >= config.min_depth)) return LineTriangulationStatus::kBehindCamera;
  if (config.max_depth > 0 && z > config.max_depth) return LineTriangulationStatus::kTooFar;
  return LineTriangulationStatus::kOk;
}
}  // namespace

const char* to_string(LineTriangulationStatus status) {
  switch (status) {
    case LineTriangulationStatus::kOk: return "ok";
    case LineTriangulationStatus::kShortSegment: return "short segment";
    case LineTriangulationStatus::kSmallPlaneAngle: return "small plane angle";
    case LineTriangulationStatus::kBehindCamera: return "behind camera";
    case LineTriangulationStatus::kTooFar: return "too far";
    case LineTriangulationStatus::kNoOverlap: return "no overlap";
  }
  return "?";
}

void LineTriangulationConfig::load(const ConfigNode& node) {
  node.get("min_plane_angle_deg", min_plane_angle_deg);
  node.get("min_depth", min_depth);
  node.get("max_depth", max_depth);
  node.get("min_segment_length", min_segment_length);
  get_choice(node, "endpoints", endpoints, kEndpointChoices);
  node.reject_unknown_keys();
}

Eigen::Vector4d back_projected_plane(const Pose& T_world_cam, const Eigen::Vector2d& start,
                                     const Eigen::Vector2d& end) {
  const Eigen::Vector3d n = (T_world_cam.linear() * line_through(start, end)).normalized();
  Eigen::Vector4d plane;
  plane << n, -n.dot(T_world_cam.translation());
  return plane;
}

TriangulatedLine triangulate_line(const Pose& T_world_cam0, const Eigen::Vector2d& start0,
                                  const Eigen::Vector2d& end0, const Pose& T_world_cam1,
                                  const Eigen::Vector2d& start1, const Eigen::Vector2d& end1,
                                  const LineTriangulationConfig& config) {
  TriangulatedLine out;
  if (!((end0 - start0).norm() >= config.min_segment_length) ||
      !((end1 - start1).norm() >= config.min_segment_length))
    return out;

  const Eigen::Vector4d plane0 = back_projected_plane(T_world_cam0, start0, end0);
  const Eigen::Vector4d plane1 = back_projected_plane(T_world_cam1, start1, end1);
  const double cos_angle = std::abs(plane0.head<3>().dot(plane1.head<3>()));
  out.plane_angle_deg = std::acos(std::min(1.0, cos_angle)) * kRadToDeg;
  if (out.plane_angle_deg < config.min_plane_angle_deg) {
    out.status = LineTriangulationStatus::kSmallPlaneAngle;
    return out;
  }

  // Endpoints seen by view 0 lie on plane 0 already; intersecting their rays with plane 1
  // puts them on the 3-D line. Same for view 1 against plane 0.
  const Pose T_cam0_world = T_world_cam0.inverse(), T_cam1_world = T_world_cam1.inverse();
  Eigen::Vector3d s0, e0, s1, e1;
  ray_plane_depth(T_world_cam0, start0, plane1, s0);
  ray_plane_depth(T_world_cam0, end0, plane1, e0);
  const bool need_view1 = config.endpoints != LineEndpointSource::kFirstView;
  if (need_view1) {
    ray_plane_depth(T_world_cam1, start1, plane0, s1);
    ray_plane_depth(T_world_cam1, end1, plane0, e1);
  }
  for (const Pose* T : {&T_cam0_world, &T_cam1_world}) {
    for (const Eigen::Vector3d* x : {&s0, &e0, &s1, &e1}) {
      if (!need_view1 && (x == &s1 || x == &e1)) continue;
      const auto status = check_depth(*T, *x, config);
      if (status != LineTriangulationStatus::kOk) {
        out.status = status;
        return out;
      }
    }
  }

  if (!need_view1) {
    out.segment_world = {s0, e0};
  } else {
    // Positions along view 0's direction; view 1's segment may run either way.
    const Eigen::Vector3d d = (e0 - s0).normalized();
    const double a0 = 0.0, b0 = d.dot(e0 - s0);
    const double a1 = std::min(d.dot(s1 - s0), d.dot(e1 - s0)), b1 = std::max(d.dot(s1 - s0), d.dot(e1 - s0));
    double lo, hi;
    if (config.endpoints == LineEndpointSource::kOverlap) {
      lo = std::max(a0, a1), hi = std::min(b0, b1);
    } else {
      lo = std::min(a0, a1), hi = std::max(b0, b1);
    }
    if (!(hi > lo)) {
      out.status = LineTriangulationStatus::kNoOverlap;
      return out;
    }
    out.segment_world = {s0 + lo * d, s0 + hi * d};
  }
  out.status = LineTriangulationStatus::kOk;
  return out;
}

}  // namespace pllvo::geometry
