#include "pllvo/geometry/vanishing.h"

#include <Eigen/Geometry>

namespace pllvo::geometry {

std::optional<double> vanishing_residual(const Eigen::Vector3d& v_cam, const Eigen::Vector2d& start,
                                         const Eigen::Vector2d& end) {
  double r = 0;
  if (!vanishing_residual<double>(v_cam, start, end, r)) return std::nullopt;
  return r;
}

Eigen::Vector3d interpretation_plane_normal(const Eigen::Vector2d& start, const Eigen::Vector2d& end) {
  return Eigen::Vector3d(start.x(), start.y(), 1.0).cross(Eigen::Vector3d(end.x(), end.y(), 1.0)).normalized();
}

}  // namespace pllvo::geometry
