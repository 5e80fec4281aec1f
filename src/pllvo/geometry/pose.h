#pragma once
// Small helpers on rigid transforms; poses are Eigen::Isometry3d named T_a_b
// (maps points from frame b to frame a).
#include <Eigen/Geometry>

namespace pllvo::geometry {

using Pose = Eigen::Isometry3d;

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

}  // namespace pllvo::geometry
