#pragma once
// 3-D lines. The map stores a line as a segment (two endpoints in the world frame): that is
// what is drawn, exported and reprojected against observed 2-D lines. The infinite line
// through it is available in Plücker coordinates for geometric operations (plane
// intersection in triangulation, transforms, the image line of a 3-D line, distances).
//
// For optimisation, backend/ keeps the endpoints and lets each one move only in the plane
// through it orthogonal to the line's direction (a minimal 4-DoF parametrisation, see
// backend/ba_costs.h); docs/geometry_backend.md explains why this was chosen over the
// orthonormal (U, W) representation.
#include <Eigen/Core>

#include "pllvo/geometry/pose.h"

namespace pllvo::geometry {

struct LineSegment3d {
  Eigen::Vector3d start = Eigen::Vector3d::Zero();
  Eigen::Vector3d end = Eigen::Vector3d::Zero();

  double length() const { return (end - start).norm(); }
  Eigen::Vector3d direction() const { return (end - start).normalized(); }
  /// The segment in frame b, given T_b_a and the segment in frame a.
  LineSegment3d transformed(const Pose& T_b_a) const { return {T_b_a * start, T_b_a * end}; }
};

/// Infinite line in Plücker coordinates: unit direction d and moment m = x × d for any point
/// x on the line (|m| is the line's distance from the origin).
struct PluckerLine {
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();

  /// The line through two distinct points, directed from a to b.
  static PluckerLine through(const Eigen::Vector3d& a, const Eigen::Vector3d& b);
  static PluckerLine through(const LineSegment3d& s) { return through(s.start, s.end); }
  /// The intersection of the planes n_i . x + d_i = 0 given as (n_i, d_i); direction n0 × n1.
  /// The planes must not be parallel.
  static PluckerLine from_planes(const Eigen::Vector4d& plane0, const Eigen::Vector4d& plane1);

  /// The same line in frame b, given T_b_a and the line in frame a.
  PluckerLine transformed(const Pose& T_b_a) const;
  /// Point of the line closest to the origin.
  Eigen::Vector3d closest_point_to_origin() const { return direction.cross(moment); }
  /// Orthogonal projection of x onto the line.
  Eigen::Vector3d project(const Eigen::Vector3d& x) const;
  double distance(const Eigen::Vector3d& x) const { return (x - project(x)).norm(); }
  /// For a line in a camera frame: its image, a normalised 2-D line (a^2 + b^2 = 1) in
  /// normalised image coordinates. Zero when the line passes through the camera centre.
  Eigen::Vector3d image_line() const;
};

}  // namespace pllvo::geometry
