#pragma once
// Vanishing points of 3-D directions: how far an image segment is from pointing at the
// vanishing point of a direction. A direction seen by a camera constrains its rotation alone
// (a point at infinity), so lines parallel to a known direction hold the heading where the
// map's points cannot (a few points on one plane, far away).
#include <optional>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace pllvo::geometry {

/// Signed distance (normalised image units) of the segment's start from the line through its
/// midpoint and the vanishing point of `v_cam` (a direction in the camera frame; the
/// vanishing point may lie at infinity). The end is as far on the other side. Empty when the
/// midpoint is the vanishing point itself.
std::optional<double> vanishing_residual(const Eigen::Vector3d& v_cam, const Eigen::Vector2d& start,
                                         const Eigen::Vector2d& end);

/// The same for any scalar (Ceres' Jets); `v_cam` need not be unit. False at the degenerate
/// midpoint.
template <typename T>
bool vanishing_residual(const Eigen::Matrix<T, 3, 1>& v_cam, const Eigen::Vector2d& start, const Eigen::Vector2d& end,
                        T& residual) {
  const Eigen::Matrix<T, 3, 1> mid(T((start.x() + end.x()) / 2), T((start.y() + end.y()) / 2), T(1));
  const Eigen::Matrix<T, 3, 1> l = mid.cross(v_cam);
  const T norm2 = l[0] * l[0] + l[1] * l[1];
  if (!(norm2 > T(1e-24) * v_cam.squaredNorm())) return false;
  residual = (l[0] * start.x() + l[1] * start.y() + l[2]) / sqrt(norm2);
  return true;
}

/// Unit normal of the plane through the camera centre and the segment (normalised image
/// coordinates): every 3-D direction the segment can have is perpendicular to it.
Eigen::Vector3d interpretation_plane_normal(const Eigen::Vector2d& start, const Eigen::Vector2d& end);

}  // namespace pllvo::geometry
