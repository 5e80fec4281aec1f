#include <cmath>

#include <gtest/gtest.h>

#include "pllvo/vo/geometry_adapter.h"

namespace pllvo::vo {
namespace {

geometry::Pose camera_at(double x, double y, double z) {
  geometry::Pose T = geometry::Pose::Identity();
  T.translation() = Eigen::Vector3d(x, y, z);
  return T;
}

TEST(TriangulationGate, BaselineSubtendsTheAngleAtTheSceneDepth) {
  // 1 deg at 4 m needs a baseline of 2 * 4 * tan(0.5 deg) = 6.98 cm; the widest view decides.
  const geometry::Pose current = camera_at(0, 0, 0);
  const double needed = 2.0 * 4.0 * std::tan(0.5 * M_PI / 180.0);
  EXPECT_TRUE(baseline_subtends({camera_at(1.01 * needed, 0, 0)}, current, 4.0, 1.0));
  EXPECT_FALSE(baseline_subtends({camera_at(0.99 * needed, 0, 0)}, current, 4.0, 1.0));
  EXPECT_TRUE(baseline_subtends({camera_at(0.01, 0, 0), camera_at(0, 0.99 * needed, 0.03)}, current, 4.0, 1.0));
  EXPECT_FALSE(baseline_subtends({camera_at(0.01, 0, 0), camera_at(0.02, 0, 0)}, current, 4.0, 1.0));
  EXPECT_FALSE(baseline_subtends({camera_at(1, 0, 0)}, current, 0.0, 1.0));  // no scene depth: no decision
}

TEST(BaselineAngle, ASevenCentimetreBaselineSubtendsOneDegreeAtFourMetres) {
  const double one_deg = 2.0 * 4.0 * std::tan(0.5 * M_PI / 180.0);  // 6.98 cm
  EXPECT_NEAR(baseline_angle_deg({0, 0, 0}, {0, one_deg, 0}, 4.0), 1.0, 1e-12);
  EXPECT_NEAR(baseline_angle_deg({0, 0, 0}, {0, 2 * one_deg, 0}, 4.0), 2.0, 1e-3);
  EXPECT_DOUBLE_EQ(baseline_angle_deg({0, 0, 3}, {0, 0, 3}, 4.0), 0.0);  // no baseline
}

TEST(TriangulationGate, MedianDepthIsTakenInTheCameraAndSkipsPointsBehindIt) {
  // Camera 1 m along z looking along +z: depths 1, 2, 3, 9 (and one point behind it, left out).
  const geometry::Pose T_world_cam = camera_at(0.3, -0.2, 1.0);
  const std::vector<Eigen::Vector3d> points = {{0.3, -0.2, 2.0}, {1.0, 0.5, 3.0}, {0.0, 0.0, 4.0},
                                               {-2.0, 1.0, 10.0}, {0.3, -0.2, 0.5}};
  EXPECT_DOUBLE_EQ(median_depth(points, T_world_cam), 3.0);
  EXPECT_DOUBLE_EQ(median_depth({}, T_world_cam), 0.0);
}

TEST(DepthUncertainty, ProjectsTheDepthErrorOfTheWidestRayPairIntoTheCamera) {
  // A point 4 m ahead of the first keyframe; the second keyframe's ray meets it at angle a.
  Pinhole cam;
  cam.fx = cam.fy = 500, cam.cx = 320, cam.cy = 240;
  const Eigen::Vector3d p(0, 0, 4);
  const std::vector<Eigen::Vector3d> centres = {{0, 0, 0}, {0.2, 0, 0}, {0.1, 0, 0}};
  const double sin_a = std::sin(std::atan2(0.2, 4.0));
  const double along = 4.0 / (500.0 * sin_a);  // map units of depth per pixel of ray noise
  // Seen from the first keyframe the depth error runs along the ray: no image motion.
  EXPECT_NEAR(depth_uncertainty_px(cam, p, centres, camera_at(0, 0, 0)), 0.0, 1e-12);
  // From (1, 0, 0) the point is at (-1, 0, 4): moving along z by `along` shifts it by
  // 500 / 4 * (1 / 4) * along pixels.
  EXPECT_NEAR(depth_uncertainty_px(cam, p, centres, camera_at(1, 0, 0)), 500.0 / 16.0 * along, 1e-9);
  // A wider baseline halves it (about); one view or a point behind the camera: unknown (1e9).
  const double wide = depth_uncertainty_px(cam, p, {{0, 0, 0}, {0.4, 0, 0}}, camera_at(1, 0, 0));
  EXPECT_NEAR(wide / (500.0 / 16.0 * along), 0.5, 0.01);
  EXPECT_EQ(depth_uncertainty_px(cam, p, {{0, 0, 0}}, camera_at(1, 0, 0)), 1e9);
  EXPECT_EQ(depth_uncertainty_px(cam, p, centres, camera_at(0, 0, 5)), 1e9);
}

}  // namespace
}  // namespace pllvo::vo
