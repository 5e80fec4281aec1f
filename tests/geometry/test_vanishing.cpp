#include <gtest/gtest.h>

#include <random>

#include "../support/synthetic_scene.h"
#include "pllvo/geometry/vanishing.h"

using namespace pllvo::geometry;
using namespace pllvo::test;

TEST(Vanishing, ResidualOfAHorizontalDirectionIsTheStartsHeightAboveTheMidpoint) {
  // Direction +x in the camera: its vanishing point lies at infinity to the right, the line
  // through the midpoint (0.1, 0.11) is y = 0.11, and the start (0, 0.1) is 0.01 off it.
  const auto r = vanishing_residual(Eigen::Vector3d(1, 0, 0), {0.0, 0.1}, {0.2, 0.12});
  ASSERT_TRUE(r.has_value());
  EXPECT_NEAR(std::abs(*r), 0.01, 1e-12);
  // A segment that points at a finite vanishing point has none.
  const Eigen::Vector3d v(0.3, -0.2, 1.0);  // vanishing point (0.3, -0.2)
  const auto zero = vanishing_residual(v * 5.0, {0.1, 0.0}, {0.2, -0.1});
  ASSERT_TRUE(zero.has_value());
  EXPECT_NEAR(*zero, 0.0, 1e-12);
  // The midpoint on the vanishing point: no line to measure from.
  EXPECT_FALSE(vanishing_residual(Eigen::Vector3d(0.15, -0.05, 1.0), {0.1, 0.0}, {0.2, -0.1}).has_value());
}

TEST(Vanishing, TrueRotationZeroesTheResidualAndATurnDoesNot) {
  std::mt19937 rng(5);
  const Pose T = random_rotation_pose(rng, Eigen::Vector3d(0.2, -0.1, 0.3), 20.0);
  const std::vector<Eigen::Vector3d> dirs = {Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(),
                                             Eigen::Vector3d::UnitZ()};
  const auto segments = segments_along(T, dirs, 5, 0.0, rng);
  const Eigen::Matrix3d R_cw = T.linear().transpose();
  const Eigen::Matrix3d turned = so3_exp(Eigen::Vector3d(0.0, 2.0 * M_PI / 180, 0.0)) * R_cw;
  double moved = 0;
  for (const auto& s : segments) {
    const auto r = vanishing_residual(R_cw * s.direction_world, s.start, s.end);
    ASSERT_TRUE(r.has_value());
    EXPECT_NEAR(*r * kFocal, 0.0, 1e-9);
    moved = std::max(moved, std::abs(*vanishing_residual(turned * s.direction_world, s.start, s.end)) * kFocal);
    // The template (Ceres' Jets) gives the double's value.
    double t = 0;
    ASSERT_TRUE(vanishing_residual<double>(turned * s.direction_world * 3.0, s.start, s.end, t));
    EXPECT_NEAR(t, *vanishing_residual(turned * s.direction_world, s.start, s.end), 1e-14);
  }
  EXPECT_GT(moved, 1.0);  // pixels: a 2 degree turn shows
}

TEST(Vanishing, InterpretationPlaneNormalIsPerpendicularToBothRays) {
  const Eigen::Vector2d a(0.1, -0.2), b(-0.3, 0.25);
  const Eigen::Vector3d n = interpretation_plane_normal(a, b);
  EXPECT_NEAR(n.norm(), 1.0, 1e-12);
  EXPECT_NEAR(n.dot(Eigen::Vector3d(a.x(), a.y(), 1)), 0.0, 1e-12);
  EXPECT_NEAR(n.dot(Eigen::Vector3d(b.x(), b.y(), 1)), 0.0, 1e-12);
}
