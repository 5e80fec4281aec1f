#include "pllvo/geometry/reprojection.h"

namespace pllvo::geometry {

bool project_normalised(const Eigen::Vector3d& p_cam, Eigen::Vector2d& xy, Matrix23d* J) {
  if (!(p_cam.z() > kMinProjectionDepth)) return false;
  const double iz = 1.0 / p_cam.z();
  xy << p_cam.x() * iz, p_cam.y() * iz;
  if (J) *J << iz, 0, -xy.x() * iz, 0, iz, -xy.y() * iz;
  return true;
}

Matrix36d point_jacobian_wrt_pose(const Eigen::Vector3d& p_cam) {
  Matrix36d J;
  J.leftCols<3>().setIdentity();
  J.rightCols<3>() = -hat(p_cam);
  return J;
}

Eigen::Vector3d line_through(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector3d l = Eigen::Vector3d(a.x(), a.y(), 1.0).cross(Eigen::Vector3d(b.x(), b.y(), 1.0));
  const double n = l.head<2>().norm();
  if (!(n > 0)) return Eigen::Vector3d::Zero();
  return l / n;
}

bool projected_point_line_distance(const Eigen::Vector3d& l, const Eigen::Vector3d& p_cam,
                                   double& distance, Eigen::RowVector3d* J) {
  Eigen::Vector2d xy;
  Matrix23d Jp;
  if (!project_normalised(p_cam, xy, J ? &Jp : nullptr)) return false;
  distance = l.x() * xy.x() + l.y() * xy.y() + l.z();
  if (J) *J = l.head<2>().transpose() * Jp;
  return true;
}

bool point_reprojection_error(const Pose& T_cam_world, const Eigen::Vector3d& p_world,
                              const Eigen::Vector2d& xy, Eigen::Vector2d& error,
                              PointErrorJacobians* J) {
  const Eigen::Vector3d p_cam = T_cam_world * p_world;
  Eigen::Vector2d proj;
  Matrix23d Jp;
  if (!project_normalised(p_cam, proj, J ? &Jp : nullptr)) return false;
  error = proj - xy;
  if (J) {
    J->pose = Jp * point_jacobian_wrt_pose(p_cam);
    J->point = Jp * T_cam_world.linear();
  }
  return true;
}

bool line_reprojection_error(const Pose& T_cam_world, const Eigen::Vector3d& start_world,
                             const Eigen::Vector3d& end_world, const Eigen::Vector3d& l,
                             Eigen::Vector2d& error, LineErrorJacobians* J) {
  const Eigen::Vector3d s_cam = T_cam_world * start_world;
  const Eigen::Vector3d e_cam = T_cam_world * end_world;
  Eigen::RowVector3d Js, Je;
  if (!projected_point_line_distance(l, s_cam, error.x(), J ? &Js : nullptr) ||
      !projected_point_line_distance(l, e_cam, error.y(), J ? &Je : nullptr))
    return false;
  if (J) {
    J->pose.row(0) = Js * point_jacobian_wrt_pose(s_cam);
    J->pose.row(1) = Je * point_jacobian_wrt_pose(e_cam);
    J->start = Js * T_cam_world.linear();
    J->end = Je * T_cam_world.linear();
  }
  return true;
}

}  // namespace pllvo::geometry
