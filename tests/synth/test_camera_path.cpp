// The drone flight: the presets' mean speed and turn rate, staying inside the free space
// and away from every surface, exact velocity, smoothness.
#include <gtest/gtest.h>

#include "pllvo/geometry/pose.h"
#include "pllvo/synth/camera_path.h"
#include "pllvo/synth/layout.h"

using namespace pllvo::synth;

class PresetFlight : public ::testing::TestWithParam<std::string> {};

TEST_P(PresetFlight, MatchesItsLevelAndStaysClearOfTheScene) {
  SequenceSpec spec = preset(GetParam());
  const Scene scene = build_scene(spec.scene, spec.seed);
  const DronePath path(spec.motion, scene, spec.seed);
  const PathStats stats = path_stats(path, 0, spec.duration_s, 20);
  EXPECT_NEAR(stats.mean_speed, spec.motion.mean_speed, 0.15 * spec.motion.mean_speed);
  EXPECT_NEAR(stats.mean_angular_rate, spec.motion.mean_angular_rate, 0.15 * spec.motion.mean_angular_rate);
  double min_clearance = 1e9, min_along_view = 1e9;
  for (double t = 0; t <= spec.duration_s; t += 0.1) {
    const Eigen::Isometry3d T = path.pose(t);
    EXPECT_TRUE(scene.free_space.contains(T.translation(), 1e-9)) << "t = " << t;
    for (const auto& q : scene.quads) min_clearance = std::min(min_clearance, distance_to_quad(q, T.translation()));
    // The camera looks at geometry at a sensible distance, not at a wall 5 cm away.
    const Eigen::Vector3d o = T.translation(), d = T.linear().col(2);
    double hit = 1e9;
    for (const auto& q : scene.quads) {
      const double denom = q.normal().dot(d);
      if (std::abs(denom) < 1e-9) continue;
      const double l = q.normal().dot(q.origin - o) / denom;
      if (l <= 0 || l >= hit) continue;
      const Eigen::Vector3d p = o + l * d - q.origin;
      const double s = p.dot(q.u) / q.u.squaredNorm(), r = p.dot(q.v) / q.v.squaredNorm();
      if (s >= 0 && s <= 1 && r >= 0 && r <= 1) hit = l;
    }
    min_along_view = std::min(min_along_view, hit);
  }
  EXPECT_GE(min_clearance, spec.scene.clearance_m - 1e-6);
  EXPECT_GE(min_along_view, spec.scene.clearance_m - 1e-6);
  EXPECT_LT(min_along_view, 1e8);  // always something in view
}

INSTANTIATE_TEST_SUITE_P(Presets, PresetFlight,
                         ::testing::Values("easy_normal", "medium_normal", "difficult_normal", "medium_lowtexture",
                                           "corridor_medium_normal"));

TEST(DronePath, LevelsAreOrderedLikeEuRoCs) {
  double prev_speed = 0, prev_rate = 0;
  for (const char* level : {"easy", "medium", "difficult"}) {
    const SequenceSpec spec = preset(std::string(level) + "_normal");
    const Scene scene = build_scene(spec.scene, spec.seed);
    const PathStats s = path_stats(DronePath(spec.motion, scene, spec.seed), 0, 30, 20);
    EXPECT_GT(s.mean_speed, prev_speed * 1.3);
    EXPECT_GT(s.mean_angular_rate, prev_rate * 1.3);
    prev_speed = s.mean_speed, prev_rate = s.mean_angular_rate;
  }
}

TEST(DronePath, VelocityIsTheDerivativeOfPositionAndMotionIsSmooth) {
  const SequenceSpec spec = preset("difficult_normal");
  const Scene scene = build_scene(spec.scene, spec.seed);
  const DronePath path(spec.motion, scene, spec.seed);
  for (double t = 0.3; t < 20; t += 1.7) {
    const double h = 1e-5;
    const Eigen::Vector3d numeric = (path.pose(t + h).translation() - path.pose(t - h).translation()) / (2 * h);
    EXPECT_LT((path.velocity(t) - numeric).norm(), 1e-6);
    // Bounded angular acceleration: the rate over 10 ms hardly changes between neighbours.
    const auto rate = [&](double a) {
      return pllvo::geometry::rotation_angle(path.pose(a).linear().transpose() * path.pose(a + 0.01).linear()) / 0.01;
    };
    EXPECT_LT(std::abs(rate(t) - rate(t + 0.01)), 0.1);
  }
}

TEST(DronePath, SameSeedSameFlightOtherSeedOtherFlight) {
  const SequenceSpec spec = preset("medium_normal");
  const Scene scene = build_scene(spec.scene, spec.seed);
  const DronePath a(spec.motion, scene, 1), b(spec.motion, scene, 1), c(spec.motion, scene, 2);
  EXPECT_TRUE(a.pose(7.3).isApprox(b.pose(7.3), 0));
  EXPECT_GT((a.pose(7.3).translation() - c.pose(7.3).translation()).norm(), 1e-3);
}

TEST(DronePath, AttitudeLooksAlongYawWithZUp) {
  const Eigen::Matrix3d R = DronePath::attitude(M_PI / 2, 0, 0);
  EXPECT_LT((R.col(2) - Eigen::Vector3d::UnitY()).norm(), 1e-12);   // forward
  EXPECT_LT((R.col(1) + Eigen::Vector3d::UnitZ()).norm(), 1e-12);   // image down = world down
  const Eigen::Matrix3d up = DronePath::attitude(0, 0.3, 0);
  EXPECT_GT(up.col(2).z(), 0.29);  // positive pitch looks up
  EXPECT_NEAR(R.determinant(), 1.0, 1e-12);
}
