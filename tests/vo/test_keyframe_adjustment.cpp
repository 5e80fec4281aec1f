#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "pllvo/vo/geometry_adapter.h"

namespace pllvo::vo {
namespace {

Pinhole camera() {
  Pinhole c;
  c.fx = c.fy = 356.0, c.cx = 376.0, c.cy = 240.0, c.width = 752, c.height = 480;
  return c;
}

geometry::Pose pose(double yaw_deg, const Eigen::Vector3d& t) {
  geometry::Pose T = geometry::Pose::Identity();
  T.linear() = Eigen::AngleAxisd(yaw_deg * M_PI / 180.0, Eigen::Vector3d::UnitY()).toRotationMatrix();
  T.translation() = t;
  return T;
}

struct Scene {
  std::vector<Eigen::Vector3d> points;  // world
  std::vector<Eigen::Vector2d> pixels;  // tracked now
};

/// Ten points 2-4 m in front of `T_world_seen`, tracked exactly where that camera sees them.
Scene scene_seen_from(const geometry::Pose& T_world_seen) {
  Scene s;
  const Pinhole cam = camera();
  for (int i = 0; i < 10; ++i) {
    const Eigen::Vector3d p_cam(-0.8 + 0.17 * i, 0.3 * std::sin(i), 2.0 + 0.2 * i);
    s.points.push_back(T_world_seen * p_cam);
    Eigen::Vector2d px;
    EXPECT_TRUE(cam.project(p_cam, px));
    s.pixels.push_back(px);
  }
  return s;
}

TEST(KeyframeAdjustment, MedianReprojectionCountsPointsBehindTheCameraAsMisses) {
  const geometry::Pose T = pose(0, {0, 0, 0});
  Scene s = scene_seen_from(T);
  EXPECT_NEAR(median_reprojection_px(camera(), s.points, s.pixels, T), 0.0, 1e-9);
  // The camera 1 cm sideways: a point at depth z misses by 356 px * 0.01 / z, z from 2 to 3.8 m.
  const double err = median_reprojection_px(camera(), s.points, s.pixels, pose(0, {0.01, 0, 0}));
  EXPECT_GT(err, 356.0 * 0.01 / 4.0);
  EXPECT_LT(err, 356.0 * 0.01 / 2.0);
  s.points[0] = Eigen::Vector3d(0, 0, -1), s.points[1] = Eigen::Vector3d(0, 0, -2);
  s.points[2] = Eigen::Vector3d(0, 0, -3), s.points[3] = Eigen::Vector3d(0, 0, -4);
  s.points[4] = Eigen::Vector3d(0, 0, -5), s.points[5] = Eigen::Vector3d(0, 0, -6);
  EXPECT_EQ(median_reprojection_px(camera(), s.points, s.pixels, T), 1e9);
  EXPECT_EQ(median_reprojection_px(camera(), {}, {}, T), 0.0);
}

TEST(KeyframeAdjustment, AWindowMovedAsAWholeMovesTheCurrentPoseWithIt) {
  // The keyframe was added at the tracker's pose; its adjustment turned it (and its points) by
  // 1.5 deg and moved it 2 cm. The camera has since moved 4 cm and turned 1 deg.
  const geometry::Pose added = pose(10, {0.5, 0, 0.2});
  const geometry::Pose adjusted = pose(11.5, {0.52, 0, 0.2});
  const geometry::Pose since = pose(1, {0.04, 0, 0.01});
  const geometry::Pose truth_now = adjusted * since;  // where the adjusted points are seen from
  const geometry::Pose tracker_now = added * since;
  const Scene s = scene_seen_from(truth_now);
  ASSERT_GT(median_reprojection_px(camera(), s.points, s.pixels, tracker_now), 4.0);
  const auto moved = follow_keyframe_adjustment(camera(), s.points, s.pixels, tracker_now, added, adjusted, 4.0);
  ASSERT_TRUE(moved.has_value());
  EXPECT_LT((moved->translation() - truth_now.translation()).norm(), 1e-9);
  EXPECT_LT(Eigen::AngleAxisd(moved->linear().transpose() * truth_now.linear()).angle(), 1e-9);
}

TEST(KeyframeAdjustment, PointsWithinTheGateOrAWorseMoveLeaveThePose) {
  const geometry::Pose added = pose(10, {0.5, 0, 0.2});
  const geometry::Pose adjusted = pose(11.5, {0.52, 0, 0.2});
  // The points agree with the tracker (within the gate): nothing moves.
  const Scene agree = scene_seen_from(added);
  EXPECT_FALSE(follow_keyframe_adjustment(camera(), agree.points, agree.pixels, added, added, adjusted, 4.0));
  // They miss the tracker, but the adjustment would move it the wrong way: nothing moves.
  const geometry::Pose elsewhere = pose(8.0, {0.48, 0, 0.2});
  const Scene off = scene_seen_from(elsewhere);
  EXPECT_FALSE(follow_keyframe_adjustment(camera(), off.points, off.pixels, added, added, adjusted, 4.0));
  // No points: nothing to decide on.
  EXPECT_FALSE(follow_keyframe_adjustment(camera(), {}, {}, added, added, adjusted, 4.0));
}

TEST(KeyframeAdjustment, MergedTracksThatMostlyMissTheTrackerGiveThePoseByPnp) {
  // The keyframe's points, followed to now, are where the true camera sees them; the tracker's
  // pose, from the few points a fast turn left it, is 2 deg and 3 cm off (~10 px at 2-4 m).
  const geometry::Pose truth_now = pose(25, {0.6, 0.05, 0.3});
  const geometry::Pose tracker_now = pose(27, {0.63, 0.05, 0.3});
  const Scene s = scene_seen_from(truth_now);
  ASSERT_GT(median_reprojection_px(camera(), s.points, s.pixels, tracker_now), 4.0);
  const geometry::PnpConfig pnp;
  const auto T = pose_of_merged_tracks(camera(), s.points, s.pixels, tracker_now, 4.0, pnp);
  ASSERT_TRUE(T.has_value());
  EXPECT_LT((T->translation() - truth_now.translation()).norm(), 1e-6);
  EXPECT_LT(Eigen::AngleAxisd(T->linear().transpose() * truth_now.linear()).angle(), 1e-6);
}

TEST(KeyframeAdjustment, MergedTracksThatFitTheTrackerOrNoPoseLeaveIt) {
  const geometry::Pose now = pose(25, {0.6, 0.05, 0.3});
  const geometry::PnpConfig pnp;
  // Most within the gate: the tracker's pose stays.
  const Scene agree = scene_seen_from(now);
  EXPECT_FALSE(pose_of_merged_tracks(camera(), agree.points, agree.pixels, now, 4.0, pnp));
  // Tracks that no pose explains (each pixel paired with another point): no PnP pose.
  Scene mixed = scene_seen_from(now);
  std::reverse(mixed.pixels.begin(), mixed.pixels.end());
  EXPECT_FALSE(pose_of_merged_tracks(camera(), mixed.points, mixed.pixels, pose(10, {0, 0, 0}), 4.0, pnp));
  EXPECT_FALSE(pose_of_merged_tracks(camera(), {}, {}, now, 4.0, pnp));
}

}  // namespace
}  // namespace pllvo::vo
