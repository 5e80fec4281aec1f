#include "pllvo/backend/ba_costs.h"

#include <ceres/product_manifold.h>

#include "pllvo/geometry/reprojection.h"
#include "pllvo/geometry/vanishing.h"

namespace pllvo::backend {

namespace {
using RowMajor27 = Eigen::Matrix<double, 2, kPoseBlockSize, Eigen::RowMajor>;
}

void pose_to_block(const Pose& T_cam0_world, double* block) {
  Eigen::Map<Eigen::Quaterniond> q(block);
  Eigen::Map<Eigen::Vector3d> t(block + 4);
  q = Eigen::Quaterniond(T_cam0_world.linear()).normalized();
  t = T_cam0_world.translation();
}

Pose block_to_pose(const double* block) {
  const Eigen::Map<const Eigen::Quaterniond> q(block);
  return geometry::make_pose(q.normalized().toRotationMatrix(), Eigen::Map<const Eigen::Vector3d>(block + 4));
}

Eigen::Matrix<double, 3, 4> rotation_jacobian_wrt_quaternion(const Eigen::Quaterniond& q, const Eigen::Vector3d& p) {
  const Eigen::Vector3d v = q.vec();
  const double w = q.w();
  Eigen::Matrix<double, 3, 4> J;
  J.leftCols<3>() = -2.0 * w * geometry::hat(p) +
                    2.0 * (v.dot(p) * Eigen::Matrix3d::Identity() + v * p.transpose() - 2.0 * p * v.transpose());
  J.col(3) = 2.0 * v.cross(p);
  return J;
}

ceres::Manifold* new_pose_manifold() {
  return new ceres::ProductManifold<ceres::EigenQuaternionManifold, ceres::EuclideanManifold<3>>{};
}

LineEndpointManifold::LineEndpointManifold(const Eigen::Vector3d& direction) {
  const Eigen::Vector3d d = direction.normalized();
  const Eigen::Vector3d u = d.unitOrthogonal();
  basis_.col(0) = u;
  basis_.col(1) = d.cross(u);
}

bool LineEndpointManifold::Plus(const double* x, const double* delta, double* x_plus_delta) const {
  for (int k = 0; k < 2; ++k)
    Eigen::Map<Eigen::Vector3d>(x_plus_delta + 3 * k) =
        Eigen::Map<const Eigen::Vector3d>(x + 3 * k) + basis_ * Eigen::Map<const Eigen::Vector2d>(delta + 2 * k);
  return true;
}

bool LineEndpointManifold::PlusJacobian(const double*, double* jacobian) const {
  Eigen::Map<Eigen::Matrix<double, 6, 4, Eigen::RowMajor>> J(jacobian);
  J.setZero();
  J.topLeftCorner<3, 2>() = basis_;
  J.bottomRightCorner<3, 2>() = basis_;
  return true;
}

bool LineEndpointManifold::Minus(const double* y, const double* x, double* y_minus_x) const {
  for (int k = 0; k < 2; ++k)
    Eigen::Map<Eigen::Vector2d>(y_minus_x + 2 * k) =
        basis_.transpose() * (Eigen::Map<const Eigen::Vector3d>(y + 3 * k) - Eigen::Map<const Eigen::Vector3d>(x + 3 * k));
  return true;
}

bool LineEndpointManifold::MinusJacobian(const double*, double* jacobian) const {
  Eigen::Map<Eigen::Matrix<double, 4, 6, Eigen::RowMajor>> J(jacobian);
  J.setZero();
  J.topLeftCorner<2, 3>() = basis_.transpose();
  J.bottomRightCorner<2, 3>() = basis_.transpose();
  return true;
}

bool PointReprojectionCost::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  const Eigen::Map<const Eigen::Quaterniond> q(parameters[0]);
  const Eigen::Map<const Eigen::Vector3d> t(parameters[0] + 4);
  const Eigen::Map<const Eigen::Vector3d> x(parameters[1]);
  const Eigen::Matrix3d R = q.toRotationMatrix();
  const Eigen::Vector3d p0 = R * x + t;
  Eigen::Vector2d xy;
  geometry::Matrix23d Jp;
  if (!geometry::project_normalised(T_cam_cam0_ * p0, xy, jacobians ? &Jp : nullptr)) return false;
  Eigen::Map<Eigen::Vector2d> r(residuals);
  r = scale_ * (xy - xy_);
  if (!jacobians) return true;
  const geometry::Matrix23d dr_dp0 = scale_ * Jp * T_cam_cam0_.linear();
  if (jacobians[0]) {
    Eigen::Map<RowMajor27> J(jacobians[0]);
    J.leftCols<4>() = dr_dp0 * rotation_jacobian_wrt_quaternion(q, x);
    J.rightCols<3>() = dr_dp0;
  }
  if (jacobians[1]) {
    Eigen::Map<Eigen::Matrix<double, 2, 3, Eigen::RowMajor>> J(jacobians[1]);
    J = dr_dp0 * R;
  }
  return true;
}

bool LineReprojectionCost::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  const Eigen::Map<const Eigen::Quaterniond> q(parameters[0]);
  const Eigen::Map<const Eigen::Vector3d> t(parameters[0] + 4);
  const Eigen::Matrix3d R = q.toRotationMatrix();
  Eigen::Matrix<double, 2, 3> dr_dp0;
  for (int k = 0; k < 2; ++k) {
    const Eigen::Map<const Eigen::Vector3d> x(parameters[1] + 3 * k);
    const Eigen::Vector3d p0 = R * x + t;
    Eigen::RowVector3d Jd;
    if (!geometry::projected_point_line_distance(line_, T_cam_cam0_ * p0, residuals[k], jacobians ? &Jd : nullptr))
      return false;
    residuals[k] *= scale_;
    if (!jacobians) continue;
    dr_dp0.row(k) = scale_ * Jd * T_cam_cam0_.linear();
    if (jacobians[0]) {
      Eigen::Map<RowMajor27> J(jacobians[0]);
      J.row(k).head<4>() = dr_dp0.row(k) * rotation_jacobian_wrt_quaternion(q, x);
      J.row(k).tail<3>() = dr_dp0.row(k);
    }
  }
  if (jacobians && jacobians[1]) {
    Eigen::Map<Eigen::Matrix<double, 2, kLineBlockSize, Eigen::RowMajor>> J(jacobians[1]);
    J.setZero();
    J.block<1, 3>(0, 0) = dr_dp0.row(0) * R;
    J.block<1, 3>(1, 3) = dr_dp0.row(1) * R;
  }
  return true;
}

bool StereoOffsetPointCost::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  double* inner_jacobians[2] = {jacobians ? jacobians[0] : nullptr, jacobians ? jacobians[1] : nullptr};
  if (!inner_->Evaluate(parameters, residuals, jacobians ? inner_jacobians : nullptr)) return false;
  residuals[0] += parameters[2][0];
  if (jacobians && jacobians[2]) jacobians[2][0] = 1, jacobians[2][1] = 0;
  return true;
}

ceres::CostFunction* new_point_cost(const Eigen::Vector2d& xy, const Pose& T_cam_cam0, double scale, bool autodiff) {
  if (!autodiff) return new PointReprojectionCost(xy, T_cam_cam0, scale);
  return new ceres::AutoDiffCostFunction<PointReprojectionFunctor, 2, kPoseBlockSize, kPointBlockSize>(
      new PointReprojectionFunctor{xy, T_cam_cam0, scale});
}

ceres::CostFunction* new_line_cost(const Eigen::Vector3d& line, const Pose& T_cam_cam0, double scale, bool autodiff) {
  if (!autodiff) return new LineReprojectionCost(line, T_cam_cam0, scale);
  return new ceres::AutoDiffCostFunction<LineReprojectionFunctor, 2, kPoseBlockSize, kLineBlockSize>(
      new LineReprojectionFunctor{line, T_cam_cam0, scale});
}

namespace {
class OffsetPriorCost final : public ceres::SizedCostFunction<1, 1> {
 public:
  explicit OffsetPriorCost(double sigma_px) : sigma_px_(sigma_px) {}
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    residuals[0] = parameters[0][0] / sigma_px_;
    if (jacobians && jacobians[0]) jacobians[0][0] = 1 / sigma_px_;
    return true;
  }

 private:
  double sigma_px_;
};
}  // namespace

ceres::CostFunction* new_offset_prior_cost(double sigma_px) { return new OffsetPriorCost(sigma_px); }

ceres::CostFunction* new_distance_cost(const Eigen::Vector3d& reference, double distance) {
  return new ceres::AutoDiffCostFunction<DistanceGaugeFunctor, 1, kPoseBlockSize>(
      new DistanceGaugeFunctor{reference, distance});
}

namespace {
struct VanishingFunctor {
  Eigen::Vector3d direction_world;
  Eigen::Vector2d start, end;
  double scale;
  template <typename T>
  bool operator()(const T* pose, T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q(pose);
    const Eigen::Matrix<T, 3, 1> v = q * direction_world.cast<T>();
    if (!geometry::vanishing_residual<T>(v, start, end, residual[0])) return false;
    residual[0] *= T(scale);
    return true;
  }
};
}  // namespace

ceres::CostFunction* new_vanishing_cost(const Eigen::Vector3d& direction_world, const Eigen::Vector2d& start,
                                        const Eigen::Vector2d& end, double scale) {
  return new ceres::AutoDiffCostFunction<VanishingFunctor, 1, kPoseBlockSize>(
      new VanishingFunctor{direction_world, start, end, scale});
}

}  // namespace pllvo::backend
