#pragma once
// Reprojection errors of points and lines in normalised image coordinates, with analytic
// Jacobians.
//
// Conventions (shared by geometry/ and backend/):
//  - Observations are undistorted normalised image coordinates xy = (X/Z, Y/Z); the front
//    end gets them from pixels with CameraModel::unproject (see normalised.h). Errors are in
//    the same units; multiply by the focal length for pixels.
//  - An observed 2-D line is l = (a, b, c) with a^2 + b^2 = 1: the infinite line
//    a x + b y + c = 0, so l . (x, y, 1) is the signed distance of (x, y) to it.
//  - Pose Jacobians are with respect to delta = (rho, phi) in T_cam_world <- (Exp(phi), rho) *
//    T_cam_world (see apply_left_increment in pose.h).
#include <Eigen/Core>

#include "pllvo/geometry/pose.h"

namespace pllvo::geometry {

/// Points closer than this to the camera plane (Z, in map units) are not projected.
constexpr double kMinProjectionDepth = 1e-6;

using Matrix23d = Eigen::Matrix<double, 2, 3>;
using Matrix26d = Eigen::Matrix<double, 2, 6>;
using Matrix36d = Eigen::Matrix<double, 3, 6>;

/// (X/Z, Y/Z); false when Z <= kMinProjectionDepth. `J` = d xy / d p_cam.
bool project_normalised(const Eigen::Vector3d& p_cam, Eigen::Vector2d& xy, Matrix23d* J = nullptr);

/// d p_cam / d delta for the left pose increment: [I, -hat(p_cam)].
Matrix36d point_jacobian_wrt_pose(const Eigen::Vector3d& p_cam);

/// Normalised coefficients of the infinite line through two image points (a^2 + b^2 = 1),
/// with the sign of the cross product (a, 1) x (b, 1). Zero when a == b.
Eigen::Vector3d line_through(const Eigen::Vector2d& a, const Eigen::Vector2d& b);

/// Signed distance of the projection of `p_cam` to the normalised line `l`; false when the
/// point is behind the camera. `J` = d distance / d p_cam.
bool projected_point_line_distance(const Eigen::Vector3d& l, const Eigen::Vector3d& p_cam,
                                   double& distance, Eigen::RowVector3d* J = nullptr);

struct PointErrorJacobians {
  Matrix26d pose;   ///< d error / d delta
  Matrix23d point;  ///< d error / d p_world
};

/// error = project(T_cam_world * p_world) - xy. False when the point is behind the camera.
bool point_reprojection_error(const Pose& T_cam_world, const Eigen::Vector3d& p_world,
                              const Eigen::Vector2d& xy, Eigen::Vector2d& error,
                              PointErrorJacobians* J = nullptr);

struct LineErrorJacobians {
  Matrix26d pose;            ///< d error / d delta
  Eigen::RowVector3d start;  ///< d error(0) / d start_world (error(0) does not depend on end)
  Eigen::RowVector3d end;    ///< d error(1) / d end_world (error(1) does not depend on start)
};

/// Line error of a 3-D segment against an observed 2-D line: the signed distances of the
/// projections of its two endpoints to the observed infinite line `l` (normalised). False
/// when an endpoint is behind the camera.
bool line_reprojection_error(const Pose& T_cam_world, const Eigen::Vector3d& start_world,
                             const Eigen::Vector3d& end_world, const Eigen::Vector3d& l,
                             Eigen::Vector2d& error, LineErrorJacobians* J = nullptr);

}  // namespace pllvo::geometry
