#include <gtest/gtest.h>

#include <cstdio>

#include "../support/synthetic_scene.h"
#include "pllvo/geometry/pnp.h"

using namespace pllvo::geometry;
using namespace pllvo::test;

namespace {
struct PnpData {
  Pose T_world_cam;
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector2d> xy;
  std::vector<uint8_t> is_outlier;
};

/// `n` points seen by one camera with 0.5 px noise; a fraction of them get a random wrong
/// observation anywhere in the image (at least 20 px from the truth).
PnpData make_data(int n, double outlier_fraction, unsigned seed) {
  const auto scene = make_scene(1, n, 0, seed);
  std::mt19937 rng(seed + 1);
  std::uniform_real_distribution<double> ux(-kHalfWidth, kHalfWidth), uy(-kHalfHeight, kHalfHeight);
  PnpData d{scene.T_world_cam[0], scene.points, {}, {}};
  const int num_outliers = static_cast<int>(outlier_fraction * n);
  for (int i = 0; i < n; ++i) {
    Eigen::Vector2d xy;
    observe(d.T_world_cam, d.points[i], xy);
    if (i < num_outliers) {
      Eigen::Vector2d wrong;
      do wrong = Eigen::Vector2d(ux(rng), uy(rng));
      while ((wrong - xy).norm() * kFocal < 20);
      d.xy.push_back(wrong);
    } else {
      d.xy.push_back(add_noise(xy, 0.5, rng));
    }
    d.is_outlier.push_back(i < num_outliers);
  }
  return d;
}
}  // namespace

TEST(PnpRansac, RecoversThePoseWithThirtyPercentOutliers) {
  for (const auto method : {PnpMethod::kAp3p, PnpMethod::kEpnp, PnpMethod::kSqpnp}) {
    for (unsigned seed : {30u, 31u, 32u}) {
      const auto d = make_data(200, 0.3, seed);
      PnpConfig config;
      config.method = method;
      const auto r = solve_pnp_ransac(d.points, d.xy, kFocal, config);
      ASSERT_TRUE(r.ok) << "seed " << seed;
      EXPECT_LT(translation_error(r.T_world_cam, d.T_world_cam), 0.02) << "seed " << seed;
      EXPECT_LT(rotation_error_deg(r.T_world_cam, d.T_world_cam), 0.1) << "seed " << seed;
      int true_inliers_found = 0, outliers_accepted = 0;
      for (size_t i = 0; i < d.xy.size(); ++i) {
        if (d.is_outlier[i]) outliers_accepted += r.inliers[i];
        else true_inliers_found += r.inliers[i];
      }
      EXPECT_EQ(outliers_accepted, 0);
      EXPECT_GE(true_inliers_found, 135);  // of 140; 2 px = 4 sigma of the 0.5 px noise
      EXPECT_EQ(r.num_inliers, true_inliers_found + outliers_accepted);
      std::printf("[ pnp ransac ] %s seed %u, 200 matches, 30%% outliers, 0.5 px noise: %.2f mm, %.4f deg, "
                  "%d/140 inliers kept, %d outliers accepted\n",
                  method == PnpMethod::kAp3p ? "ap3p" : method == PnpMethod::kEpnp ? "epnp" : "sqpnp", seed,
                  1e3 * translation_error(r.T_world_cam, d.T_world_cam), rotation_error_deg(r.T_world_cam, d.T_world_cam),
                  true_inliers_found, outliers_accepted);
    }
  }
}

TEST(PnpRansac, FailsCleanlyOnTooFewOrInconsistentMatches) {
  const auto d = make_data(8, 0.0, 33);
  PnpConfig config;
  EXPECT_FALSE(solve_pnp_ransac(d.points, d.xy, kFocal, config).ok);  // fewer than min_inliers

  // Only outliers: no pose explains 10 of them.
  const auto bad = make_data(60, 1.0, 34);
  const auto r = solve_pnp_ransac(bad.points, bad.xy, kFocal, config);
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.inliers.size(), 60u);
}
