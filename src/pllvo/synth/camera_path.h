#pragma once
// Continuous-time camera trajectories: T_world_cam0(t) and the velocity of cam0's centre.
#include <cstdint>
#include <vector>

#include <Eigen/Geometry>

#include "pllvo/synth/scene.h"
#include "pllvo/synth/spec.h"

namespace pllvo::synth {

class CameraPath {
 public:
  virtual ~CameraPath() = default;
  virtual Eigen::Isometry3d pose(double t) const = 0;  ///< T_world_cam0
  /// Velocity of cam0's centre in the world frame (central difference unless overridden).
  virtual Eigen::Vector3d velocity(double t) const;
};

/// A fixed pose (tests).
class StaticPath final : public CameraPath {
 public:
  explicit StaticPath(const Eigen::Isometry3d& T_world_cam) : T_(T_world_cam) {}
  Eigen::Isometry3d pose(double) const override { return T_; }
  Eigen::Vector3d velocity(double) const override { return Eigen::Vector3d::Zero(); }

 private:
  Eigen::Isometry3d T_;
};

/// Constant linear velocity (world) and angular velocity (camera frame) from a start pose.
class ConstantVelocityPath final : public CameraPath {
 public:
  ConstantVelocityPath(const Eigen::Isometry3d& T_world_cam0, const Eigen::Vector3d& v_world,
                       const Eigen::Vector3d& omega_cam)
      : T0_(T_world_cam0), v_(v_world), w_(omega_cam) {}
  Eigen::Isometry3d pose(double t) const override;
  Eigen::Vector3d velocity(double) const override { return v_; }

 private:
  Eigen::Isometry3d T0_;
  Eigen::Vector3d v_, w_;
};

/// Drone-like flight: each position axis and yaw/pitch/roll is a sum of incommensurate
/// sinusoids (smooth, bounded), plus a steady yaw drift and optional fast jitter. The
/// amplitudes keep the camera inside the scene's free space; the time scales are solved
/// so that the mean speed and mean angular rate equal the spec's.
class DronePath final : public CameraPath {
 public:
  DronePath(const MotionSpec& motion, const Scene& scene, uint64_t seed);
  Eigen::Isometry3d pose(double t) const override;
  Eigen::Vector3d velocity(double t) const override;

  struct Wave {
    double amplitude, omega, phase;  ///< omega in rad/s at time scale 1
  };

  /// Rotation of a camera with the given yaw (about world z), pitch (up positive) and roll.
  static Eigen::Matrix3d attitude(double yaw, double pitch, double roll);

 private:
  Eigen::Vector3d position(double t) const;
  Eigen::Vector3d angles(double t) const;  ///< yaw, pitch, roll

  Eigen::Vector3d centre_;
  std::vector<Wave> pos_[3], pos_shake_[3];
  std::vector<Wave> rot_[3], rot_shake_[3];
  double yaw0_ = 0, yaw_drift_ = 0;
  double pos_rate_ = 1, rot_rate_ = 1;
};

/// Mean speed and mean angular rate of a path over [t0, t1] (sampled at `hz`).
struct PathStats {
  double mean_speed = 0, mean_angular_rate = 0, max_angular_rate = 0;
};
PathStats path_stats(const CameraPath& path, double t0, double t1, double hz = 50);

}  // namespace pllvo::synth
