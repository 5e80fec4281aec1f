#pragma once
// Ceres residuals and manifolds of the sliding-window bundle adjustment.
//
// Parameter blocks:
//  - pose (7): T_cam0_world as [qx qy qz qw tx ty tz] (Eigen quaternion order) on
//    ProductManifold<EigenQuaternionManifold, EuclideanManifold<3>>;
//  - point (3): p_world;
//  - line (6): [start_world, end_world] on LineEndpointManifold: each endpoint moves only in
//    the plane through it orthogonal to the line direction at construction. A line crossing
//    two parallel planes is fixed by its two crossing points, so this is a minimal (4-DoF)
//    parametrisation of the infinite line with no gauge freedom along it, and the segment
//    keeps its extent. It is singular only for a line turned 90 degrees, far outside the
//    range of one bundle-adjustment update.
// Residuals are in pixels (normalised error * focal_px) so that loss scales are in pixels.
// Analytic Jacobians are the default; the autodiff functors compute the same residuals and
// serve as the reference in tests and as the baseline in bench_backend.
#include <ceres/autodiff_cost_function.h>
#include <ceres/manifold.h>
#include <ceres/sized_cost_function.h>

#include <memory>

#include <Eigen/Geometry>

#include "pllvo/geometry/pose.h"

namespace pllvo::backend {

using geometry::Pose;

constexpr int kPoseBlockSize = 7;
constexpr int kPointBlockSize = 3;
constexpr int kLineBlockSize = 6;

/// Pose block <-> pose (T_cam0_world).
void pose_to_block(const Pose& T_cam0_world, double* block);
Pose block_to_pose(const double* block);

/// d (R(q) p) / d (qx, qy, qz, qw) for a unit quaternion, using the formula
/// R(q) p = p + 2 w (v x p) + 2 v x (v x p), v = (qx, qy, qz).
Eigen::Matrix<double, 3, 4> rotation_jacobian_wrt_quaternion(const Eigen::Quaterniond& q, const Eigen::Vector3d& p);

/// Pose manifold of the 7-parameter pose block (caller owns).
ceres::Manifold* new_pose_manifold();

class LineEndpointManifold final : public ceres::Manifold {
 public:
  /// `direction`: the line direction at construction (need not be unit).
  explicit LineEndpointManifold(const Eigen::Vector3d& direction);
  int AmbientSize() const override { return 6; }
  int TangentSize() const override { return 4; }
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override;
  bool PlusJacobian(const double* x, double* jacobian) const override;
  bool Minus(const double* y, const double* x, double* y_minus_x) const override;
  bool MinusJacobian(const double* x, double* jacobian) const override;

 private:
  Eigen::Matrix<double, 3, 2> basis_;  ///< orthonormal, orthogonal to the direction
};

/// Point reprojection residual: focal_px * (project(T_cam_cam0 * T_cam0_world * p) - xy).
class PointReprojectionCost final : public ceres::SizedCostFunction<2, kPoseBlockSize, kPointBlockSize> {
 public:
  PointReprojectionCost(const Eigen::Vector2d& xy, const Pose& T_cam_cam0, double scale)
      : xy_(xy), T_cam_cam0_(T_cam_cam0), scale_(scale) {}
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

 private:
  Eigen::Vector2d xy_;
  Pose T_cam_cam0_;
  double scale_;
};

/// Line residual: scale * signed distances of both projected endpoints to the observed line.
class LineReprojectionCost final : public ceres::SizedCostFunction<2, kPoseBlockSize, kLineBlockSize> {
 public:
  LineReprojectionCost(const Eigen::Vector3d& line, const Pose& T_cam_cam0, double scale)
      : line_(line), T_cam_cam0_(T_cam_cam0), scale_(scale) {}
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

 private:
  Eigen::Vector3d line_;
  Pose T_cam_cam0_;
  double scale_;
};

/// The same residuals for ceres::AutoDiffCostFunction.
struct PointReprojectionFunctor {
  Eigen::Vector2d xy;
  Pose T_cam_cam0;
  double scale;

  template <typename T>
  bool operator()(const T* pose, const T* point, T* residual) const {
    const Eigen::Matrix<T, 3, 1> p = to_camera(pose, point);
    if (!(p.z() > T(1e-6))) return false;
    residual[0] = T(scale) * (p.x() / p.z() - T(xy.x()));
    residual[1] = T(scale) * (p.y() / p.z() - T(xy.y()));
    return true;
  }

  template <typename T>
  Eigen::Matrix<T, 3, 1> to_camera(const T* pose, const T* x) const {
    const Eigen::Quaternion<T> q(pose[3], pose[0], pose[1], pose[2]);
    const Eigen::Matrix<T, 3, 1> p0 = q * Eigen::Matrix<T, 3, 1>(x[0], x[1], x[2]) +
                                      Eigen::Matrix<T, 3, 1>(pose[4], pose[5], pose[6]);
    return T_cam_cam0.linear().cast<T>() * p0 + T_cam_cam0.translation().cast<T>();
  }
};

struct LineReprojectionFunctor {
  Eigen::Vector3d line;
  Pose T_cam_cam0;
  double scale;

  template <typename T>
  bool operator()(const T* pose, const T* ends, T* residual) const {
    const PointReprojectionFunctor transform{Eigen::Vector2d::Zero(), T_cam_cam0, scale};
    for (int k = 0; k < 2; ++k) {
      const Eigen::Matrix<T, 3, 1> p = transform.to_camera(pose, ends + 3 * k);
      if (!(p.z() > T(1e-6))) return false;
      residual[k] = T(scale) * (T(line.x()) * p.x() / p.z() + T(line.y()) * p.y() / p.z() + T(line.z()));
    }
    return true;
  }
};

/// Keeps a camera's centre at `distance` from a fixed point (a monocular map's scale):
/// residual kDistanceGaugeWeight * (|c - reference| / distance - 1), c the centre of the
/// T_cam0_world block.
struct DistanceGaugeFunctor {
  Eigen::Vector3d reference;
  double distance;

  template <typename T>
  bool operator()(const T* pose, T* residual) const {
    const Eigen::Quaternion<T> q(pose[3], pose[0], pose[1], pose[2]);
    const Eigen::Matrix<T, 3, 1> centre = -(q.conjugate() * Eigen::Matrix<T, 3, 1>(pose[4], pose[5], pose[6]));
    residual[0] = T(kDistanceGaugeWeight) * ((centre - reference.cast<T>()).norm() / T(distance) - T(1));
    return true;
  }
  /// 1 % of the distance weighs as 1 px of reprojection error. No other residual depends on
  /// the scale, so the minimum keeps the distance whatever the weight; a stiffer one only
  /// slows the solver along the sphere.
  static constexpr double kDistanceGaugeWeight = 100;
};

/// A right-camera point residual with the rectified pair's horizontal offset (pixels, a
/// 1-parameter block) added to its x: blocks pose, point, offset. Wraps `inner` (owned).
class StereoOffsetPointCost final : public ceres::SizedCostFunction<2, kPoseBlockSize, kPointBlockSize, 1> {
 public:
  explicit StereoOffsetPointCost(ceres::CostFunction* inner) : inner_(inner) {}
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

 private:
  std::unique_ptr<ceres::CostFunction> inner_;
};

/// Cost functions, analytic or automatic differentiation (caller owns).
ceres::CostFunction* new_point_cost(const Eigen::Vector2d& xy, const Pose& T_cam_cam0, double scale, bool autodiff);
ceres::CostFunction* new_line_cost(const Eigen::Vector3d& line, const Pose& T_cam_cam0, double scale, bool autodiff);
ceres::CostFunction* new_distance_cost(const Eigen::Vector3d& reference, double distance);
/// Zero-mean prior on the 1-parameter stereo offset block: residual offset / sigma_px.
ceres::CostFunction* new_offset_prior_cost(double sigma_px);

/// Vanishing-point error (geometry::vanishing_residual, times `scale`) of a segment seen
/// parallel to `direction_world`, on the keyframe pose block alone.
ceres::CostFunction* new_vanishing_cost(const Eigen::Vector3d& direction_world, const Eigen::Vector2d& start,
                                        const Eigen::Vector2d& end, double scale);

}  // namespace pllvo::backend
