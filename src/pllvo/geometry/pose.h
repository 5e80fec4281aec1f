#pragma once
// Small helpers on rigid transforms; poses are Eigen::Isometry3d named T_a_b
// (maps points from frame b to frame a).
#include <cmath>

#include <Eigen/Geometry>
#include <Eigen/SVD>

namespace pllvo::geometry {

using Pose = Eigen::Isometry3d;
using Vector6d = Eigen::Matrix<double, 6, 1>;

inline Pose make_pose(const Eigen::Matrix3d& R, const Eigen::Vector3d& t) {
  Pose T = Pose::Identity();
  T.linear() = R;
  T.translation() = t;
  return T;
}

/// Rotation angle in radians, in [0, pi], robust near 0 and pi.
inline double rotation_angle(const Eigen::Matrix3d& R) {
  const Eigen::Quaterniond q(R);
  return 2.0 * std::atan2(q.vec().norm(), std::abs(q.w()));
}

/// The rotation nearest to M in the Frobenius norm: U V^T of its SVD, with the last axis
/// flipped where that would be a reflection. Wahba's problem (M = sum of b a^T over pairs that
/// should satisfy b = R a) and re-orthonormalising a nearly orthonormal frame are both this.
inline Eigen::Matrix3d nearest_rotation(const Eigen::Matrix3d& M) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0) D(2, 2) = -1;
  return svd.matrixU() * D * svd.matrixV().transpose();
}

/// Skew-symmetric matrix: hat(a) * b == a.cross(b).
inline Eigen::Matrix3d hat(const Eigen::Vector3d& v) {
  Eigen::Matrix3d S;
  S << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return S;
}

/// Rotation matrix of a rotation vector (axis * angle).
inline Eigen::Matrix3d so3_exp(const Eigen::Vector3d& phi) {
  const double angle = phi.norm();
  if (angle < 1e-12) return Eigen::Matrix3d::Identity() + hat(phi);
  return Eigen::AngleAxisd(angle, phi / angle).toRotationMatrix();
}

/// Rotation vector of a rotation matrix, angle in [0, pi].
inline Eigen::Vector3d so3_log(const Eigen::Matrix3d& R) {
  const Eigen::Quaterniond q(R);
  const double n = q.vec().norm();
  if (n < 1e-12) return 2.0 * q.vec() * (q.w() < 0 ? -1.0 : 1.0);
  // Shortest rotation: flip the quaternion to w >= 0 so the angle stays in [0, pi].
  const double sign = q.w() < 0 ? -1.0 : 1.0;
  return (2.0 * std::atan2(n, std::abs(q.w())) / n) * sign * q.vec();
}

/// The increment convention of every pose Jacobian in pllvo::geometry and pllvo::backend:
/// T <- (Exp(phi), rho) * T with delta = (rho, phi), so a point p = T * x moves to
/// p + rho + phi x p to first order (d p / d delta = [I, -hat(p)]).
inline Pose apply_left_increment(const Vector6d& delta, const Pose& T) {
  return make_pose(so3_exp(delta.tail<3>()), delta.head<3>()) * T;
}

}  // namespace pllvo::geometry
