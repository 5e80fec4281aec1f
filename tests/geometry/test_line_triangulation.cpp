#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "../support/synthetic_scene.h"
#include "pllvo/geometry/line_triangulation.h"

using namespace pllvo::geometry;
using namespace pllvo::test;

namespace {
struct Observed {
  Eigen::Vector2d s0, e0, s1, e1;
};

Observed observe_both(const SyntheticScene& scene, const LineSegment3d& s, double sigma_px, std::mt19937& rng) {
  Observed o;
  observe_line(scene.T_world_cam[0], s, sigma_px, rng, &o.s0, &o.e0);
  observe_line(scene.T_world_cam[1], s, sigma_px, rng, &o.s1, &o.e1);
  return o;
}

TriangulatedLine triangulate(const SyntheticScene& scene, const Observed& o, const LineTriangulationConfig& config = {}) {
  return triangulate_line(scene.T_world_cam[0], o.s0, o.e0, scene.T_world_cam[1], o.s1, o.e1, config);
}
}  // namespace

TEST(LineTriangulation, ExactObservationsGiveTheExactSegment) {
  const auto scene = make_scene(2, 0, 100, 20, 1.0);
  std::mt19937 rng(21);
  int ok = 0;
  for (const auto& s : scene.lines) {
    const auto r = triangulate(scene, observe_both(scene, s, 0.0, rng));
    if (r.status == LineTriangulationStatus::kSmallPlaneAngle) continue;  // near-epipolar lines
    ASSERT_TRUE(r.ok()) << to_string(r.status);
    EXPECT_LT((r.segment_world.start - s.start).norm(), 1e-8);
    EXPECT_LT((r.segment_world.end - s.end).norm(), 1e-8);
    ++ok;
  }
  EXPECT_GT(ok, 80);
  std::printf("[ line triangulation ] noise-free: %d of 100 lines accepted, all exact\n", ok);
}

TEST(LineTriangulation, NoisyAccuracy) {
  // 0.5 px endpoint noise, 1 m baseline, depths 4-10 m, plane angle >= 3 deg: the
  // reconstructed endpoints lie within about 1-2% of their depth from the true line (two-view
  // point triangulation with this baseline: ~0.8%; the plane angle costs a little more).
  const auto scene = make_scene(2, 0, 300, 22, 1.0);
  std::mt19937 rng(23);
  LineTriangulationConfig config;
  config.min_plane_angle_deg = 3.0;
  std::vector<double> rel_err;
  for (const auto& s : scene.lines) {
    const auto r = triangulate(scene, observe_both(scene, s, 0.5, rng), config);
    if (!r.ok()) continue;
    EXPECT_GE(r.plane_angle_deg, 3.0);
    const double depth = (scene.T_world_cam[0].inverse() * (0.5 * (s.start + s.end))).z();
    const double err = std::max(distance_to_line(r.segment_world.start, s), distance_to_line(r.segment_world.end, s));
    rel_err.push_back(err / depth);
  }
  ASSERT_GT(rel_err.size(), 100u);
  std::sort(rel_err.begin(), rel_err.end());
  const double median = rel_err[rel_err.size() / 2], p90 = rel_err[rel_err.size() * 9 / 10];
  EXPECT_LT(median, 0.02);
  EXPECT_LT(p90, 0.05);
  std::printf("[ line triangulation ] %zu of %zu lines accepted, endpoint-to-true-line distance / depth: "
              "median %.2f%%, p90 %.2f%%\n", rel_err.size(), scene.lines.size(), 100 * median, 100 * p90);
}

TEST(LineTriangulation, RejectsLinesInTheEpipolarPlane) {
  // A horizontal line seen by two cameras displaced horizontally: both back-projected planes
  // contain the baseline, so they coincide.
  const std::vector<Pose> T = {Pose::Identity(), make_pose(Eigen::Matrix3d::Identity(), Eigen::Vector3d(0.5, 0, 0))};
  const LineSegment3d s{{-1, 0.5, 5}, {1, 0.5, 5}};  // parallel to the baseline
  Eigen::Vector2d s0, e0, s1, e1;
  observe(T[0], s.start, s0), observe(T[0], s.end, e0), observe(T[1], s.start, s1), observe(T[1], s.end, e1);
  const auto r = triangulate_line(T[0], s0, e0, T[1], s1, e1);
  EXPECT_EQ(r.status, LineTriangulationStatus::kSmallPlaneAngle);
  EXPECT_LT(r.plane_angle_deg, 1e-6);

  // The same line tilted out of the epipolar plane is fine.
  const LineSegment3d tilted{{-1, 0.0, 5}, {1, 1.0, 6}};
  observe(T[0], tilted.start, s0), observe(T[0], tilted.end, e0), observe(T[1], tilted.start, s1),
      observe(T[1], tilted.end, e1);
  const auto ok = triangulate_line(T[0], s0, e0, T[1], s1, e1);
  EXPECT_TRUE(ok.ok()) << to_string(ok.status);
}

TEST(LineTriangulation, EndpointSourcesOverlapAndUnion) {
  const std::vector<Pose> T = {Pose::Identity(), make_pose(Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitY()).toRotationMatrix(),
                                                           Eigen::Vector3d(0.5, 0.2, 0))};
  const LineSegment3d s{{-1, -1, 5}, {-0.5, 1.5, 6}};
  const auto at = [&](double u) -> Eigen::Vector3d { return s.start + u * (s.end - s.start); };
  // View 0 saw [0, 0.7] of the segment, view 1 saw [0.4, 1] (reversed direction).
  Eigen::Vector2d s0, e0, s1, e1;
  observe(T[0], at(0.0), s0), observe(T[0], at(0.7), e0), observe(T[1], at(1.0), s1), observe(T[1], at(0.4), e1);
  LineTriangulationConfig config;
  for (auto [source, lo, hi] : {std::tuple{LineEndpointSource::kFirstView, 0.0, 0.7},
                                std::tuple{LineEndpointSource::kOverlap, 0.4, 0.7},
                                std::tuple{LineEndpointSource::kUnion, 0.0, 1.0}}) {
    config.endpoints = source;
    const auto r = triangulate_line(T[0], s0, e0, T[1], s1, e1, config);
    ASSERT_TRUE(r.ok()) << to_string(r.status);
    EXPECT_LT((r.segment_world.start - at(lo)).norm(), 1e-9);
    EXPECT_LT((r.segment_world.end - at(hi)).norm(), 1e-9);
  }
  // Disjoint extents have no overlap.
  observe(T[1], at(0.8), s1), observe(T[1], at(1.0), e1);
  config.endpoints = LineEndpointSource::kOverlap;
  EXPECT_EQ(triangulate_line(T[0], s0, e0, T[1], s1, e1, config).status, LineTriangulationStatus::kNoOverlap);
}

TEST(LineTriangulation, RejectsShortSegmentsAndLinesBehindTheCameras) {
  const std::vector<Pose> T = {Pose::Identity(), make_pose(Eigen::Matrix3d::Identity(), Eigen::Vector3d(0.5, 0, 0))};
  const Eigen::Vector2d a(0.1, 0.1);
  EXPECT_EQ(triangulate_line(T[0], a, a, T[1], a, Eigen::Vector2d(0.2, 0.3)).status,
            LineTriangulationStatus::kShortSegment);
  // A vertical line whose planes intersect behind the cameras: view 1 sees it to the left
  // of where a line in front would appear.
  const auto r = triangulate_line(T[0], Eigen::Vector2d(0.1, -0.2), Eigen::Vector2d(0.1, 0.2), T[1],
                                  Eigen::Vector2d(0.2, -0.2), Eigen::Vector2d(0.2, 0.2));
  EXPECT_EQ(r.status, LineTriangulationStatus::kBehindCamera) << to_string(r.status);
}
