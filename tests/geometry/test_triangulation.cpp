#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "../support/synthetic_scene.h"
#include "pllvo/geometry/triangulation.h"

using namespace pllvo::geometry;
using namespace pllvo::test;

namespace {
double reprojection_cost(std::span<const Pose> T_cam_world, std::span<const Eigen::Vector2d> xy,
                         const Eigen::Vector3d& p) {
  double sum = 0;
  for (size_t i = 0; i < xy.size(); ++i) {
    Eigen::Vector2d e;
    point_reprojection_error(T_cam_world[i], p, xy[i], e);
    sum += e.squaredNorm();
  }
  return sum;
}

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}
}  // namespace

TEST(PointTriangulation, ExactObservationsGiveTheExactPoint) {
  const auto scene = make_scene(2, 100, 0, 10);
  for (const auto& p : scene.points) {
    std::vector<Eigen::Vector2d> xy(2);
    observe(scene.T_world_cam[0], p, xy[0]);
    observe(scene.T_world_cam[1], p, xy[1]);
    const auto r = triangulate_point(scene.T_world_cam, xy, kFocal);
    ASSERT_TRUE(r.ok()) << to_string(r.status);
    EXPECT_LT((r.p_world - p).norm(), 1e-9);
    EXPECT_LT(r.max_error_px, 1e-6);
  }
}

TEST(PointTriangulation, NoisyTwoAndFiveViewAccuracy) {
  // 0.5 px noise, 4-10 m depth. Depth error ~ z^2 sigma / (f b): a 0.3 m baseline gives
  // ~2.6% at 7 m; five views spanning 1.2 m give ~0.6%.
  std::mt19937 rng(11);
  for (int views : {2, 5}) {
    const auto scene = make_scene(views, 300, 0, 12);
    std::vector<double> rel_err;
    for (const auto& p : scene.points) {
      std::vector<Eigen::Vector2d> xy(views);
      std::vector<Pose> T_cw(views);
      for (int i = 0; i < views; ++i) {
        observe(scene.T_world_cam[i], p, xy[i]);
        xy[i] = add_noise(xy[i], 0.5, rng);
        T_cw[i] = scene.T_world_cam[i].inverse();
      }
      PointTriangulationConfig config;
      config.min_parallax_deg = 0.5;
      const auto r = triangulate_point(scene.T_world_cam, xy, kFocal, config);
      if (!r.ok()) continue;
      // Refinement minimises the reprojection error the DLT only approximates.
      Eigen::Vector3d dlt;
      ASSERT_TRUE(triangulate_linear(T_cw, xy, dlt));
      EXPECT_LE(reprojection_cost(T_cw, xy, r.p_world), reprojection_cost(T_cw, xy, dlt) + 1e-15);
      rel_err.push_back((r.p_world - p).norm() / (T_cw[0] * p).z());
      EXPECT_LT(r.max_error_px, 2.0);
    }
    ASSERT_GT(rel_err.size(), 250u) << views << " views";
    const double m = median(rel_err);
    EXPECT_LT(m, views == 2 ? 0.035 : 0.008) << views << " views";
    std::printf("[ triangulation ] %d views, 0.5 px noise: median error %.2f%% of depth\n", views, 100 * m);
  }
}

TEST(PointTriangulation, RejectsLowParallax) {
  // Two cameras 1 cm apart looking at a point 10 m away: parallax ~0.06 deg.
  const std::vector<Pose> T = {Pose::Identity(), make_pose(Eigen::Matrix3d::Identity(), Eigen::Vector3d(0.01, 0, 0))};
  const Eigen::Vector3d p(0.5, 0.2, 10);
  std::vector<Eigen::Vector2d> xy(2);
  observe(T[0], p, xy[0]);
  observe(T[1], p, xy[1]);
  const auto r = triangulate_point(T, xy, kFocal);
  EXPECT_EQ(r.status, TriangulationStatus::kLowParallax);
  EXPECT_NEAR(r.parallax_deg, 0.0573, 0.002);
}

TEST(PointTriangulation, RejectsPointsBehindACamera) {
  // Rays that only meet behind the cameras: a point 5 m in front seen by camera 0, and
  // camera 1 observing it mirrored so that its ray crosses camera 0's behind both.
  const std::vector<Pose> T = {Pose::Identity(), make_pose(Eigen::Matrix3d::Identity(), Eigen::Vector3d(1, 0, 0))};
  const std::vector<Eigen::Vector2d> xy = {Eigen::Vector2d(0.1, 0), Eigen::Vector2d(0.3, 0)};
  const auto r = triangulate_point(T, xy, kFocal);
  EXPECT_EQ(r.status, TriangulationStatus::kBehindCamera) << to_string(r.status);
}

TEST(PointTriangulation, RejectsAnInconsistentObservation) {
  const auto scene = make_scene(3, 1, 0, 13);
  std::vector<Eigen::Vector2d> xy(3);
  for (int i = 0; i < 3; ++i) observe(scene.T_world_cam[i], scene.points[0], xy[i]);
  xy[2].x() += 20.0 / kFocal;  // a 20-pixel mismatch in the third view
  const auto r = triangulate_point(scene.T_world_cam, xy, kFocal);
  EXPECT_EQ(r.status, TriangulationStatus::kLargeError);
  EXPECT_GT(r.max_error_px, 2.0);
}

TEST(PointTriangulation, RejectsFarPointsAndTooFewViews) {
  const auto scene = make_scene(2, 20, 0, 14);
  PointTriangulationConfig config;
  config.max_depth = 5.0;
  config.min_parallax_deg = 0.5;
  int too_far = 0, ok = 0;
  for (const auto& p : scene.points) {
    std::vector<Eigen::Vector2d> xy(2);
    observe(scene.T_world_cam[0], p, xy[0]);
    observe(scene.T_world_cam[1], p, xy[1]);
    const auto r = triangulate_point(scene.T_world_cam, xy, kFocal, config);
    const bool far = (scene.T_world_cam[0].inverse() * p).z() > 5.0 || (scene.T_world_cam[1].inverse() * p).z() > 5.0;
    if (r.status == TriangulationStatus::kLowParallax) continue;
    EXPECT_EQ(r.status, far ? TriangulationStatus::kTooFar : TriangulationStatus::kOk);
    (far ? too_far : ok)++;
  }
  EXPECT_GT(too_far, 0);
  EXPECT_GT(ok, 0);
  const std::vector<Eigen::Vector2d> one = {Eigen::Vector2d::Zero()};
  EXPECT_EQ(triangulate_point(std::span(scene.T_world_cam).first(1), one, kFocal).status,
            TriangulationStatus::kTooFewViews);
}
