#include <gtest/gtest.h>

#include <random>

#include "pllvo/geometry/stereo_triangulation.h"

using namespace pllvo::geometry;
using pllvo::camera::PinholeIntrinsics;

namespace {
const PinholeIntrinsics kRect{435.2, 435.2, 367.5, 252.2};  // a rectified EuRoC-like pair
constexpr double kBaseline = 0.11;

Eigen::Vector2d pixel(const Eigen::Vector3d& p) {
  return {kRect.fx * p.x() / p.z() + kRect.cx, kRect.fy * p.y() / p.z() + kRect.cy};
}
}  // namespace

TEST(StereoTriangulation, DepthIsFocalTimesBaselineOverDisparity) {
  std::mt19937 rng(50);
  std::uniform_real_distribution<double> ux(-2, 2), uy(-1, 1), uz(0.5, 15);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d p(ux(rng), uy(rng), uz(rng));
    const Eigen::Vector2d l = pixel(p), r = pixel(p - Eigen::Vector3d(kBaseline, 0, 0));
    const auto s = triangulate_stereo(l, r, kRect, kBaseline);
    ASSERT_TRUE(s.ok()) << to_string(s.status);
    EXPECT_NEAR(s.disparity_px, kRect.fx * kBaseline / p.z(), 1e-9);
    EXPECT_LT((s.p_left - p).norm(), 1e-9 * p.z());
  }
}

TEST(StereoTriangulation, NoisyDepthErrorFollowsTheDisparityNoise) {
  // 0.3 px disparity noise: relative depth error ~ 0.3 / disparity.
  std::mt19937 rng(51);
  std::normal_distribution<double> noise(0, 0.3 / std::sqrt(2.0));
  const Eigen::Vector3d p(0.4, -0.2, 3.0);
  const double disparity = kRect.fx * kBaseline / p.z();  // ~16 px
  double sum2 = 0;
  const int n = 2000;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d l = pixel(p) + Eigen::Vector2d(noise(rng), noise(rng));
    const Eigen::Vector2d r = pixel(p - Eigen::Vector3d(kBaseline, 0, 0)) + Eigen::Vector2d(noise(rng), noise(rng));
    const auto s = triangulate_stereo(l, r, kRect, kBaseline);
    ASSERT_TRUE(s.ok());
    sum2 += (s.p_left.z() - p.z()) * (s.p_left.z() - p.z());
  }
  const double rel_rms = std::sqrt(sum2 / n) / p.z();
  EXPECT_NEAR(rel_rms, 0.3 / disparity, 0.25 * 0.3 / disparity);
}

TEST(StereoTriangulation, RejectsBadMatches) {
  StereoTriangulationConfig config;
  config.max_depth = 20;
  config.max_disparity_px = 200;
  const Eigen::Vector2d l(400, 250);
  EXPECT_EQ(triangulate_stereo(l, Eigen::Vector2d(380, 253), kRect, kBaseline, config).status, StereoStatus::kEpipolar);
  EXPECT_EQ(triangulate_stereo(l, Eigen::Vector2d(410, 250), kRect, kBaseline, config).status,
            StereoStatus::kSmallDisparity);  // negative disparity
  EXPECT_EQ(triangulate_stereo(l, Eigen::Vector2d(399.5, 250), kRect, kBaseline, config).status,
            StereoStatus::kSmallDisparity);
  EXPECT_EQ(triangulate_stereo(l, Eigen::Vector2d(150, 250), kRect, kBaseline, config).status,
            StereoStatus::kLargeDisparity);
  EXPECT_EQ(triangulate_stereo(l, Eigen::Vector2d(398, 250), kRect, kBaseline, config).status,
            StereoStatus::kTooFar);  // 435.2 * 0.11 / 2 = 23.9 m
  config.max_disparity_px = 0;
  config.min_depth = 0.5;
  EXPECT_EQ(triangulate_stereo(l, Eigen::Vector2d(250, 250), kRect, kBaseline, config).status,
            StereoStatus::kTooClose);  // 0.32 m
  const std::vector<Eigen::Vector2d> left = {l, l}, right = {Eigen::Vector2d(380, 250.4), Eigen::Vector2d(380, 260)};
  const auto many = triangulate_stereo(left, right, kRect, kBaseline, config);
  ASSERT_EQ(many.size(), 2u);
  EXPECT_TRUE(many[0].ok());
  EXPECT_EQ(many[1].status, StereoStatus::kEpipolar);
}
