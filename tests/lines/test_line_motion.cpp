#include <gtest/gtest.h>

#include <random>

#include "pllvo/features/lines/line_motion.h"

using namespace pllvo::lines;
using V = Eigen::Vector2d;

namespace {
struct Case {
  LineSegment line;
  LineMotion truth;
};

// Samples along the line, moved by eq. 6 with noise; `outliers` of them thrown far off.
void make_samples(const Case& c, int n, double noise, double outlier_share, uint64_t seed, std::vector<V>& before,
                  std::vector<V>& after) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> gauss(0.0, noise);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  before.clear();
  after.clear();
  for (int i = 0; i < n; ++i) {
    const V p = c.line.at((i + 0.5) / n);
    V q = c.truth.apply(p, c.line.start) + V(gauss(rng), gauss(rng));
    if (i % 10 < outlier_share * 10) q += V(u(rng), u(rng)).normalized() * (4.0 + 12.0 * std::abs(u(rng)));
    before.push_back(p);
    after.push_back(q);
  }
}

std::vector<Case> cases() {
  return {{LineSegment(V(100, 80), V(300, 120)), {2.3, -1.7, 0.012}},
          {LineSegment(V(400, 400), V(380, 250)), {-5.1, 3.3, -0.02}},
          {LineSegment(V(50, 300), V(120, 300)), {0.4, 7.9, 0.005}},
          {LineSegment(V(600, 50), V(700, 150)), {-0.2, -0.3, -0.0004}}};
}
}  // namespace

// Eq. 6 from noisy analytic samples: < 0.05 px and < 0.001 rad (Done-when criterion).
TEST(LineMotion, RecoversKnownMotionFromNoisySamples) {
  std::vector<V> before, after;
  uint64_t seed = 1;
  for (const auto& c : cases()) {
    make_samples(c, 60, 0.05, 0.0, seed++, before, after);
    const LineMotionFit fit = fit_line_motion(c.line, before, after, {});
    ASSERT_TRUE(fit.valid);
    EXPECT_LT(std::abs(fit.motion.g1 - c.truth.g1), 0.05);
    EXPECT_LT(std::abs(fit.motion.g2 - c.truth.g2), 0.05);
    EXPECT_LT(std::abs(fit.motion.g3 - c.truth.g3), 0.001);
    EXPECT_EQ(fit.inliers, 60);
    EXPECT_NEAR(fit.rms_normal_px, 0.05, 0.02);
    EXPECT_NEAR(fit.stretch, 1.0, 0.01);
  }
}

TEST(LineMotion, RobustToOutlierSamples) {
  std::vector<V> before, after;
  uint64_t seed = 11;
  for (const auto& c : cases()) {
    make_samples(c, 60, 0.05, 0.2, seed++, before, after);  // 20% thrown 4..16 px off
    const LineMotionFit fit = fit_line_motion(c.line, before, after, {});
    ASSERT_TRUE(fit.valid);
    EXPECT_LT(std::abs(fit.motion.g1 - c.truth.g1), 0.05);
    EXPECT_LT(std::abs(fit.motion.g2 - c.truth.g2), 0.05);
    EXPECT_LT(std::abs(fit.motion.g3 - c.truth.g3), 0.001);
    EXPECT_EQ(fit.inliers, 48);
  }
}

TEST(LineMotion, ExactSamplesGiveExactMotionAndMovedSegment) {
  const Case c = cases()[0];
  std::vector<V> before, after;
  make_samples(c, 5, 0.0, 0.0, 1, before, after);
  const LineMotionFit fit = fit_line_motion(c.line, before, after, {});
  ASSERT_TRUE(fit.valid);
  EXPECT_NEAR(fit.motion.g1, c.truth.g1, 1e-9);
  EXPECT_NEAR(fit.motion.g2, c.truth.g2, 1e-9);
  EXPECT_NEAR(fit.motion.g3, c.truth.g3, 1e-12);
  const LineSegment moved = fit.motion.apply(c.line);
  EXPECT_TRUE(moved.start.isApprox(c.line.start + V(c.truth.g1, c.truth.g2)));
  EXPECT_TRUE(moved.end.isApprox(c.truth.apply(c.line.end, c.line.start)));
}

TEST(LineMotion, StretchAndDegenerateInput) {
  const LineSegment line(V(0, 0), V(100, 0));
  std::vector<V> before, after;
  for (int i = 0; i <= 10; ++i) {
    before.push_back(line.at(i / 10.0));
    after.push_back(V(1.2 * before.back().x(), 0.0));  // samples spread by 20% along the line
  }
  LineMotionFitConfig loose;
  loose.inlier_tangential_px = 100.0;
  const LineMotionFit fit = fit_line_motion(line, before, after, loose);
  ASSERT_TRUE(fit.valid);
  EXPECT_NEAR(fit.stretch, 1.2, 1e-6);
  // One sample, or all samples at one point: no motion can be fitted.
  EXPECT_FALSE(fit_line_motion(line, {V(1, 1)}, {V(2, 2)}, {}).valid);
  EXPECT_FALSE(fit_line_motion(line, {V(1, 1), V(1, 1), V(1, 1)}, {V(2, 2), V(2, 2), V(2, 2)}, {}).valid);
}
