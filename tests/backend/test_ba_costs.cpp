#include <gtest/gtest.h>

#include <memory>

#include "../support/synthetic_scene.h"
#include "pllvo/backend/ba_costs.h"

using namespace pllvo::backend;
using namespace pllvo::test;

namespace {
/// A stereo-like extrinsic, so the tests also cover observations by a second camera.
const Pose kRight = pllvo::geometry::make_pose(Eigen::AngleAxisd(0.02, Eigen::Vector3d::UnitY()).toRotationMatrix(),
                                               Eigen::Vector3d(-0.11, 0.001, 0.002));

struct Evaluated {
  Eigen::Vector2d r;
  Eigen::Matrix<double, 2, 7, Eigen::RowMajor> J_pose;
  Eigen::Matrix<double, 2, Eigen::Dynamic, Eigen::RowMajor> J_landmark;
};

Evaluated evaluate(const ceres::CostFunction& cost, const double* pose, const double* landmark, int landmark_size) {
  Evaluated e;
  e.J_landmark.resize(2, landmark_size);
  const double* params[2] = {pose, landmark};
  double* jac[2] = {e.J_pose.data(), e.J_landmark.data()};
  EXPECT_TRUE(cost.Evaluate(params, e.r.data(), jac));
  return e;
}

/// Tangent-space Jacobian by central differences through the manifold's Plus.
Eigen::MatrixXd numeric_tangent_jacobian(const ceres::CostFunction& cost, const ceres::Manifold& manifold,
                                         std::vector<double> pose, std::vector<double> landmark, bool wrt_pose) {
  std::vector<double>& x = wrt_pose ? pose : landmark;
  const int n = manifold.TangentSize();
  Eigen::MatrixXd J(2, n);
  const double h = 1e-6;
  for (int k = 0; k < n; ++k) {
    std::vector<double> delta(n, 0.0), xp(x.size()), xm(x.size());
    delta[k] = h;
    manifold.Plus(x.data(), delta.data(), xp.data());
    delta[k] = -h;
    manifold.Plus(x.data(), delta.data(), xm.data());
    Eigen::Vector2d rp, rm;
    const std::vector<double> saved = x;
    x = xp;
    const double* pp[2] = {pose.data(), landmark.data()};
    cost.Evaluate(pp, rp.data(), nullptr);
    x = xm;
    const double* pm[2] = {pose.data(), landmark.data()};
    cost.Evaluate(pm, rm.data(), nullptr);
    x = saved;
    J.col(k) = (rp - rm) / (2 * h);
  }
  return J;
}

Eigen::MatrixXd plus_jacobian(const ceres::Manifold& m, const double* x) {
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> J(m.AmbientSize(), m.TangentSize());
  m.PlusJacobian(x, J.data());
  return J;
}

std::vector<double> pose_block(const Pose& T_world_cam) {
  std::vector<double> b(7);
  pose_to_block(T_world_cam.inverse(), b.data());
  return b;
}
}  // namespace

TEST(BaCosts, PoseBlockRoundTrip) {
  const auto scene = make_scene(3, 0, 0, 60);
  for (const auto& T : scene.T_world_cam) {
    const auto b = pose_block(T);
    const Pose back = block_to_pose(b.data()).inverse();
    EXPECT_LT((back.matrix() - T.matrix()).norm(), 1e-12);
  }
}

TEST(BaCosts, QuaternionRotationJacobian) {
  const Eigen::Quaterniond q = Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, -2, 0.5).normalized()));
  const Eigen::Vector3d p(0.3, -1.2, 4.0);
  const auto rotate = [&](const Eigen::Vector4d& c) {  // the formula, valid on the unit sphere
    const Eigen::Vector3d v = c.head<3>();
    return Eigen::Vector3d(p + 2 * c.w() * v.cross(p) + 2 * v.cross(v.cross(p)));
  };
  EXPECT_LT((rotate(q.coeffs()) - q * p).norm(), 1e-12);
  const auto J = rotation_jacobian_wrt_quaternion(q, p);
  for (int k = 0; k < 4; ++k) {
    Eigen::Vector4d d = Eigen::Vector4d::Zero();
    d[k] = 1e-6;
    const Eigen::Vector3d num = (rotate(q.coeffs() + d) - rotate(q.coeffs() - d)) / 2e-6;
    EXPECT_LT((num - J.col(k)).norm(), 1e-8);
  }
}

TEST(BaCosts, PointCostAnalyticMatchesAutodiffAndNumeric) {
  const auto scene = make_scene(3, 30, 0, 61);
  std::mt19937 rng(62);
  const std::unique_ptr<ceres::Manifold> pose_manifold(new_pose_manifold());
  const ceres::EuclideanManifold<3> point_manifold;
  for (const Pose& extrinsic : {Pose(Pose::Identity()), kRight}) {
    for (const auto& T : scene.T_world_cam) {
      const auto pose = pose_block(T);
      for (const auto& p : scene.points) {
        Eigen::Vector2d xy;
        ASSERT_TRUE(observe(T * extrinsic.inverse(), p, xy));
        xy = add_noise(xy, 2.0, rng);
        const PointReprojectionCost analytic(xy, extrinsic, kFocal);
        const std::unique_ptr<ceres::CostFunction> autodiff(new_point_cost(xy, extrinsic, kFocal, true));
        const Evaluated a = evaluate(analytic, pose.data(), p.data(), 3);
        const Evaluated b = evaluate(*autodiff, pose.data(), p.data(), 3);
        EXPECT_LT((a.r - b.r).norm(), 1e-9);
        EXPECT_LT((a.J_pose - b.J_pose).norm(), 1e-8 * (1 + a.J_pose.norm()));
        EXPECT_LT((a.J_landmark - b.J_landmark).norm(), 1e-8 * (1 + a.J_landmark.norm()));
        EXPECT_LT(a.r.norm(), 20.0);  // pixels: the 2 px noise, not a frame mix-up

        const std::vector<double> pt(p.data(), p.data() + 3);
        const Eigen::MatrixXd Jt = a.J_pose * plus_jacobian(*pose_manifold, pose.data());
        const Eigen::MatrixXd Jn = numeric_tangent_jacobian(analytic, *pose_manifold, pose, pt, true);
        EXPECT_LT((Jt - Jn).norm(), 1e-5 * (1 + Jt.norm()));
        const Eigen::MatrixXd Jl = numeric_tangent_jacobian(analytic, point_manifold, pose, pt, false);
        EXPECT_LT((a.J_landmark - Jl).norm(), 1e-5 * (1 + Jl.norm()));
      }
    }
  }
}

TEST(BaCosts, StereoOffsetCostAddsTheOffsetToXAndPassesTheInnerJacobians) {
  const auto scene = make_scene(2, 10, 0, 63);
  const auto pose = pose_block(scene.T_world_cam[1]);
  for (const auto& p : scene.points) {
    Eigen::Vector2d xy;
    ASSERT_TRUE(observe(scene.T_world_cam[1] * kRight.inverse(), p, xy));
    const PointReprojectionCost plain(xy, kRight, kFocal);
    const StereoOffsetPointCost shifted(new PointReprojectionCost(xy, kRight, kFocal));
    const double offset = 0.7;
    const double* params[3] = {pose.data(), p.data(), &offset};
    Eigen::Vector2d r;
    Eigen::Matrix<double, 2, 7, Eigen::RowMajor> J_pose;
    Eigen::Matrix<double, 2, 3, Eigen::RowMajor> J_point;
    Eigen::Vector2d J_offset;
    double* jac[3] = {J_pose.data(), J_point.data(), J_offset.data()};
    ASSERT_TRUE(shifted.Evaluate(params, r.data(), jac));
    const Evaluated e = evaluate(plain, pose.data(), p.data(), 3);
    EXPECT_NEAR(r.x(), e.r.x() + offset, 1e-12);
    EXPECT_NEAR(r.y(), e.r.y(), 1e-12);
    EXPECT_LT((J_pose - e.J_pose).norm(), 1e-12);
    EXPECT_LT((J_point - e.J_landmark).norm(), 1e-12);
    EXPECT_EQ(J_offset, Eigen::Vector2d(1, 0));
    // Some Jacobians asked for, others not (Ceres passes null for constant blocks).
    double* only_offset[3] = {nullptr, nullptr, J_offset.data()};
    J_offset.setZero();
    ASSERT_TRUE(shifted.Evaluate(params, r.data(), only_offset));
    EXPECT_EQ(J_offset, Eigen::Vector2d(1, 0));
  }
}

TEST(BaCosts, LineCostAnalyticMatchesAutodiffAndNumeric) {
  const auto scene = make_scene(3, 0, 20, 63);
  std::mt19937 rng(64);
  const std::unique_ptr<ceres::Manifold> pose_manifold(new_pose_manifold());
  for (const Pose& extrinsic : {Pose(Pose::Identity()), kRight}) {
    for (const auto& T : scene.T_world_cam) {
      const auto pose = pose_block(T);
      for (const auto& s : scene.lines) {
        const Eigen::Vector3d l = observe_line(T * extrinsic.inverse(), s, 2.0, rng);
        std::vector<double> ends = {s.start.x(), s.start.y(), s.start.z(), s.end.x(), s.end.y(), s.end.z()};
        const LineEndpointManifold line_manifold(s.end - s.start);
        const LineReprojectionCost analytic(l, extrinsic, kFocal);
        const std::unique_ptr<ceres::CostFunction> autodiff(new_line_cost(l, extrinsic, kFocal, true));
        const Evaluated a = evaluate(analytic, pose.data(), ends.data(), 6);
        const Evaluated b = evaluate(*autodiff, pose.data(), ends.data(), 6);
        EXPECT_LT((a.r - b.r).norm(), 1e-9);
        EXPECT_LT((a.J_pose - b.J_pose).norm(), 1e-8 * (1 + a.J_pose.norm()));
        EXPECT_LT((a.J_landmark - b.J_landmark).norm(), 1e-8 * (1 + a.J_landmark.norm()));

        const Eigen::MatrixXd Jt = a.J_pose * plus_jacobian(*pose_manifold, pose.data());
        EXPECT_LT((Jt - numeric_tangent_jacobian(analytic, *pose_manifold, pose, ends, true)).norm(), 1e-5 * (1 + Jt.norm()));
        const Eigen::MatrixXd Jl = a.J_landmark * plus_jacobian(line_manifold, ends.data());
        EXPECT_LT((Jl - numeric_tangent_jacobian(analytic, line_manifold, pose, ends, false)).norm(), 1e-5 * (1 + Jl.norm()));
      }
    }
  }
}

TEST(BaCosts, ExactObservationsHaveZeroResidual) {
  const auto scene = make_scene(1, 5, 5, 65);
  std::mt19937 rng(66);
  const auto pose = pose_block(scene.T_world_cam[0]);
  for (const auto& p : scene.points) {
    Eigen::Vector2d xy;
    observe(scene.T_world_cam[0], p, xy);
    EXPECT_LT(evaluate(PointReprojectionCost(xy, Pose::Identity(), kFocal), pose.data(), p.data(), 3).r.norm(), 1e-9);
  }
  for (const auto& s : scene.lines) {
    const Eigen::Vector3d l = observe_line(scene.T_world_cam[0], s, 0.0, rng);
    const double ends[6] = {s.start.x(), s.start.y(), s.start.z(), s.end.x(), s.end.y(), s.end.z()};
    EXPECT_LT(evaluate(LineReprojectionCost(l, Pose::Identity(), kFocal), pose.data(), ends, 6).r.norm(), 1e-9);
  }
}

TEST(LineEndpointManifold, MovesEndpointsOrthogonallyToTheLine) {
  const Eigen::Vector3d start(0.1, 0.2, 5), end(1.0, -0.4, 6.5);
  const LineEndpointManifold m(end - start);
  EXPECT_EQ(m.AmbientSize(), 6);
  EXPECT_EQ(m.TangentSize(), 4);
  const double x[6] = {start.x(), start.y(), start.z(), end.x(), end.y(), end.z()};
  const double delta[4] = {0.03, -0.02, 0.05, 0.01};
  double y[6], back[4];
  m.Plus(x, delta, y);
  const Eigen::Vector3d d = (end - start).normalized();
  EXPECT_NEAR((Eigen::Map<const Eigen::Vector3d>(y) - start).dot(d), 0.0, 1e-15);
  EXPECT_NEAR((Eigen::Map<const Eigen::Vector3d>(y + 3) - end).dot(d), 0.0, 1e-15);
  EXPECT_NEAR((Eigen::Map<const Eigen::Vector3d>(y) - start).norm(), std::hypot(0.03, 0.02), 1e-15);
  m.Minus(y, x, back);
  for (int k = 0; k < 4; ++k) EXPECT_NEAR(back[k], delta[k], 1e-15);
  Eigen::Matrix<double, 4, 6, Eigen::RowMajor> Jm;
  m.MinusJacobian(x, Jm.data());
  EXPECT_LT((Jm * plus_jacobian(m, x) - Eigen::Matrix4d::Identity()).norm(), 1e-15);
}
