#include <gtest/gtest.h>

#include "../support/synthetic_scene.h"
#include "pllvo/geometry/line3d.h"
#include "pllvo/geometry/reprojection.h"

using namespace pllvo::geometry;
using pllvo::test::make_scene;

namespace {
constexpr double kStep = 1e-6;

Pose perturbed(const Pose& T, int k, double h) {
  Vector6d d = Vector6d::Zero();
  d[k] = h;
  return apply_left_increment(d, T);
}
}  // namespace

TEST(Reprojection, LineThroughIsNormalisedAndContainsBothPoints) {
  const Eigen::Vector2d a(0.1, -0.3), b(-0.4, 0.25);
  const Eigen::Vector3d l = line_through(a, b);
  EXPECT_NEAR(l.head<2>().norm(), 1.0, 1e-15);
  EXPECT_NEAR(l.dot(Eigen::Vector3d(a.x(), a.y(), 1)), 0.0, 1e-15);
  EXPECT_NEAR(l.dot(Eigen::Vector3d(b.x(), b.y(), 1)), 0.0, 1e-15);
  // Signed distance of a point one unit off the line along its normal.
  const Eigen::Vector2d c = a + l.head<2>();
  EXPECT_NEAR(l.dot(Eigen::Vector3d(c.x(), c.y(), 1)), 1.0, 1e-12);
  EXPECT_EQ(line_through(a, a), Eigen::Vector3d::Zero());
}

TEST(Reprojection, PointErrorAndJacobiansMatchFiniteDifferences) {
  const auto scene = make_scene(3, 20, 0, 1);
  for (const auto& T_wc : scene.T_world_cam) {
    const Pose T = T_wc.inverse();
    for (const auto& p : scene.points) {
      const Eigen::Vector2d xy(0.01, -0.02);
      Eigen::Vector2d e;
      PointErrorJacobians J;
      ASSERT_TRUE(point_reprojection_error(T, p, xy, e, &J));
      Eigen::Vector2d proj;
      project_normalised(T * p, proj);
      EXPECT_TRUE(e.isApprox(proj - xy, 1e-14));
      for (int k = 0; k < 6; ++k) {
        Eigen::Vector2d ep, em;
        point_reprojection_error(perturbed(T, k, kStep), p, xy, ep);
        point_reprojection_error(perturbed(T, k, -kStep), p, xy, em);
        EXPECT_LT(((ep - em) / (2 * kStep) - J.pose.col(k)).norm(), 1e-7 * (1 + J.pose.col(k).norm()));
      }
      for (int k = 0; k < 3; ++k) {
        Eigen::Vector3d d = Eigen::Vector3d::Zero();
        d[k] = kStep;
        Eigen::Vector2d ep, em;
        point_reprojection_error(T, p + d, xy, ep);
        point_reprojection_error(T, p - d, xy, em);
        EXPECT_LT(((ep - em) / (2 * kStep) - J.point.col(k)).norm(), 1e-7 * (1 + J.point.col(k).norm()));
      }
    }
  }
}

TEST(Reprojection, LineErrorIsEndpointDistanceToObservedLine) {
  const auto scene = make_scene(3, 0, 20, 2);
  std::mt19937 rng(3);
  for (const auto& T_wc : scene.T_world_cam) {
    const Pose T = T_wc.inverse();
    for (const auto& s : scene.lines) {
      // Noise-free observation: zero error, whatever part of the line was observed.
      const Eigen::Vector3d l = pllvo::test::observe_line(T_wc, s, 0.0, rng);
      Eigen::Vector2d e;
      ASSERT_TRUE(line_reprojection_error(T, s.start, s.end, l, e));
      EXPECT_LT(e.norm(), 1e-12);
      const Eigen::Vector3d shifted_start = s.start + 0.3 * (s.end - s.start);
      ASSERT_TRUE(line_reprojection_error(T, shifted_start, s.end, l, e));
      EXPECT_LT(e.norm(), 1e-12);

      // Moving the observed line by dist along its normal changes both errors by -dist.
      const double dist = 0.004;
      Eigen::Vector3d l_moved = l;
      l_moved.z() -= dist;
      ASSERT_TRUE(line_reprojection_error(T, s.start, s.end, l_moved, e));
      EXPECT_NEAR(e.x(), -dist, 1e-12);
      EXPECT_NEAR(e.y(), -dist, 1e-12);
    }
  }
}

TEST(Reprojection, LineJacobiansMatchFiniteDifferences) {
  const auto scene = make_scene(3, 0, 20, 4);
  std::mt19937 rng(5);
  for (const auto& T_wc : scene.T_world_cam) {
    const Pose T = T_wc.inverse();
    for (const auto& s : scene.lines) {
      const Eigen::Vector3d l = pllvo::test::observe_line(T_wc, s, 3.0, rng);  // nonzero error
      Eigen::Vector2d e;
      LineErrorJacobians J;
      ASSERT_TRUE(line_reprojection_error(T, s.start, s.end, l, e, &J));
      for (int k = 0; k < 6; ++k) {
        Eigen::Vector2d ep, em;
        line_reprojection_error(perturbed(T, k, kStep), s.start, s.end, l, ep);
        line_reprojection_error(perturbed(T, k, -kStep), s.start, s.end, l, em);
        EXPECT_LT(((ep - em) / (2 * kStep) - J.pose.col(k)).norm(), 1e-7 * (1 + J.pose.col(k).norm()));
      }
      for (int k = 0; k < 3; ++k) {
        Eigen::Vector3d d = Eigen::Vector3d::Zero();
        d[k] = kStep;
        Eigen::Vector2d sp, sm, ep, em;
        line_reprojection_error(T, s.start + d, s.end, l, sp);
        line_reprojection_error(T, s.start - d, s.end, l, sm);
        line_reprojection_error(T, s.start, s.end + d, l, ep);
        line_reprojection_error(T, s.start, s.end - d, l, em);
        EXPECT_NEAR((sp.x() - sm.x()) / (2 * kStep), J.start[k], 1e-7 * (1 + J.start.norm()));
        EXPECT_NEAR((ep.y() - em.y()) / (2 * kStep), J.end[k], 1e-7 * (1 + J.end.norm()));
        EXPECT_EQ(sp.y(), sm.y());  // error(1) does not depend on the start point
        EXPECT_EQ(ep.x(), em.x());
      }
    }
  }
}

TEST(Reprojection, PointsBehindTheCameraAreNotProjected) {
  Eigen::Vector2d e;
  EXPECT_FALSE(point_reprojection_error(Pose::Identity(), Eigen::Vector3d(0, 0, -1), Eigen::Vector2d::Zero(), e));
  EXPECT_FALSE(line_reprojection_error(Pose::Identity(), Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(0, 0, -1),
                                       Eigen::Vector3d(1, 0, 0), e));
}

TEST(Plucker, ImageLineMatchesProjectedEndpointsAndTransformsConsistently) {
  const auto scene = make_scene(2, 0, 10, 6);
  for (const auto& s : scene.lines) {
    const PluckerLine L = PluckerLine::through(s);
    EXPECT_NEAR(L.direction.dot(L.moment), 0.0, 1e-12);
    EXPECT_LT(L.distance(s.start), 1e-12);
    EXPECT_LT(L.distance(0.3 * s.start + 0.7 * s.end), 1e-12);
    EXPECT_NEAR(L.distance(s.start + L.moment.normalized()), 1.0, 1e-12);
    for (const auto& T_wc : scene.T_world_cam) {
      const Pose T_cw = T_wc.inverse();
      const PluckerLine Lc = L.transformed(T_cw);
      const PluckerLine Lc_direct = PluckerLine::through(s.transformed(T_cw));
      EXPECT_LT((Lc.moment - Lc_direct.moment).norm(), 1e-12);
      Eigen::Vector2d a, b;
      project_normalised(T_cw * s.start, a);
      project_normalised(T_cw * s.end, b);
      const Eigen::Vector3d l = Lc.image_line();
      const Eigen::Vector3d expected = line_through(a, b);
      EXPECT_LT(std::min((l - expected).norm(), (l + expected).norm()), 1e-9);
    }
  }
}

TEST(Plucker, IntersectionOfTwoPlanes) {
  // Planes x = 1 and y = 2 meet in the line {(1, 2, z)}.
  const PluckerLine L = PluckerLine::from_planes(Eigen::Vector4d(1, 0, 0, -1), Eigen::Vector4d(0, 1, 0, -2));
  EXPECT_TRUE(L.direction.isApprox(Eigen::Vector3d(0, 0, 1)));
  EXPECT_TRUE(L.closest_point_to_origin().isApprox(Eigen::Vector3d(1, 2, 0)));
  EXPECT_NEAR(L.distance(Eigen::Vector3d(1, 2, 7)), 0.0, 1e-12);
}
