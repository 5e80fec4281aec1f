#include "pllvo/geometry/two_view_refine.h"

#include <ceres/autodiff_cost_function.h>
#include <ceres/loss_function.h>
#include <ceres/manifold.h>
#include <ceres/problem.h>
#include <ceres/solver.h>
#include <ceres/sphere_manifold.h>

namespace pllvo::geometry::two_view_detail {

namespace {
/// Sampson distance (pixels) of a match to the epipolar geometry E = [t]x R.
struct SampsonError {
  Eigen::Vector2d x0, x1;
  double focal;

  template <typename T>
  bool operator()(const T* q_xyzw, const T* t, T* residual) const {
    const Eigen::Quaternion<T> q(q_xyzw[3], q_xyzw[0], q_xyzw[1], q_xyzw[2]);
    Eigen::Matrix<T, 3, 3> tx;
    tx << T(0), -t[2], t[1], t[2], T(0), -t[0], -t[1], t[0], T(0);
    const Eigen::Matrix<T, 3, 3> E = tx * q.toRotationMatrix();
    const Eigen::Matrix<T, 3, 1> h0(T(x0.x()), T(x0.y()), T(1)), h1(T(x1.x()), T(x1.y()), T(1));
    const Eigen::Matrix<T, 3, 1> l1 = E * h0, l0 = E.transpose() * h1;
    const T denom = l1.x() * l1.x() + l1.y() * l1.y() + l0.x() * l0.x() + l0.y() * l0.y();
    if (!(denom > T(1e-30))) return false;
    residual[0] = T(focal) * h1.dot(l1) / sqrt(denom);
    return true;
  }
};

}  // namespace

void refine_motion(Eigen::Matrix3d& R, Eigen::Vector3d& t, std::span<const Eigen::Vector2d> xy0,
                   std::span<const Eigen::Vector2d> xy1, const std::vector<uint8_t>& inliers, double focal_px,
                   double sigma_px, const DirectionPrior* prior, const std::vector<DirectionPairError>* pairs) {
  Eigen::Quaterniond q(R);
  double q_xyzw[4] = {q.x(), q.y(), q.z(), q.w()};
  double tt[3] = {t.x(), t.y(), t.z()};
  ceres::Problem problem;
  ceres::LossFunction* loss = new ceres::HuberLoss(2.0 * sigma_px);
  for (size_t i = 0; i < xy0.size(); ++i) {
    if (!inliers[i]) continue;
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<SampsonError, 1, 4, 3>(
                                 new SampsonError{xy0[i], xy1[i], focal_px}),
                             loss, q_xyzw, tt);
  }
  if (problem.NumResidualBlocks() < 6) {
    delete loss;
    return;
  }
  if (prior)
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<DirectionPrior, 3, 3>(new DirectionPrior(*prior)),
                             nullptr, tt);
  if (pairs)
    for (const auto& p : *pairs)
      problem.AddResidualBlock(new ceres::AutoDiffCostFunction<DirectionPairError, 3, 4>(new DirectionPairError(p)),
                               nullptr, q_xyzw);
  problem.SetManifold(q_xyzw, new ceres::EigenQuaternionManifold);
  problem.SetManifold(tt, new ceres::SphereManifold<3>);
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = 20;
  options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  if (!summary.IsSolutionUsable()) return;
  R = Eigen::Quaterniond(q_xyzw[3], q_xyzw[0], q_xyzw[1], q_xyzw[2]).normalized().toRotationMatrix();
  t = Eigen::Vector3d(tt[0], tt[1], tt[2]).normalized();
}


double sampson_px(const Eigen::Matrix3d& R, const Eigen::Vector3d& t, const Eigen::Vector2d& x0,
                  const Eigen::Vector2d& x1, double focal_px) {
  const Eigen::Quaterniond q(R);
  const double q_xyzw[4] = {q.x(), q.y(), q.z(), q.w()};
  double r = 0;
  if (!SampsonError{x0, x1, focal_px}(q_xyzw, t.data(), &r)) return 0.0;
  return r;
}


}  // namespace pllvo::geometry::two_view_detail
