#include "pllvo/geometry/line3d.h"

namespace pllvo::geometry {

PluckerLine PluckerLine::through(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  PluckerLine L;
  L.direction = (b - a).normalized();
  L.moment = a.cross(L.direction);
  return L;
}

PluckerLine PluckerLine::from_planes(const Eigen::Vector4d& plane0, const Eigen::Vector4d& plane1) {
  const Eigen::Vector3d n0 = plane0.head<3>(), n1 = plane1.head<3>();
  const Eigen::Vector3d d = n0.cross(n1);
  const double s = d.norm();
  // x × (n0 × n1) = n0 (x.n1) - n1 (x.n0) = d0 n1 - d1 n0 for any x on both planes.
  PluckerLine L;
  L.direction = d / s;
  L.moment = (plane0.w() * n1 - plane1.w() * n0) / s;
  return L;
}

PluckerLine PluckerLine::transformed(const Pose& T_b_a) const {
  PluckerLine L;
  L.direction = T_b_a.linear() * direction;
  L.moment = T_b_a.linear() * moment + T_b_a.translation().cross(L.direction);
  return L;
}

Eigen::Vector3d PluckerLine::project(const Eigen::Vector3d& x) const {
  const Eigen::Vector3d p0 = closest_point_to_origin();
  return p0 + direction * direction.dot(x - p0);
}

Eigen::Vector3d PluckerLine::image_line() const {
  const double n = moment.head<2>().norm();
  if (!(n > 0)) return Eigen::Vector3d::Zero();
  return moment / n;
}

}  // namespace pllvo::geometry
