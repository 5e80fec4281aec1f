#include <gtest/gtest.h>

#include <random>

#include "pllvo/features/lines/collinear_merge.h"
#include "pllvo/features/lines/line_fit.h"

using namespace pllvo::lines;
using V = Eigen::Vector2d;

TEST(LineFit, TotalLeastSquaresIsIsotropic) {
  // A steep line (y = a + bx would be ill-conditioned) with perpendicular noise.
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.2);
  const V p0(100, 50), d = V(0.05, 1.0).normalized(), n(-d.y(), d.x());
  std::vector<V> pts;
  for (int i = 0; i <= 200; ++i) pts.push_back(p0 + i * d + noise(rng) * n);
  const LineFit fit = fit_line_tls(pts);
  EXPECT_LT(std::acos(std::min(1.0, std::abs(fit.direction.dot(d)))), 0.003);
  EXPECT_LT(std::abs(n.dot(fit.centroid - p0)), 0.05);
  EXPECT_NEAR(fit.rms_distance, 0.2, 0.03);
  const LineSegment s = segment_from_fit(fit, pts, LineSegment(p0, p0 + 200 * d));
  EXPECT_LT((s.start - p0).norm(), 0.5);
  EXPECT_LT((s.end - (p0 + 200 * d)).norm(), 0.5);
}

TEST(CollinearMerge, MergesPiecesOfOneLineOnly) {
  const CollinearMergeConfig config;  // 2 deg, 1.5 px, gap 8 px
  const LineSegment a(V(0, 10), V(50, 10));
  EXPECT_TRUE(can_merge(a, LineSegment(V(55, 10.4), V(90, 10.6)), config));   // gap 5
  EXPECT_TRUE(can_merge(a, LineSegment(V(30, 10.2), V(70, 10.2)), config));   // overlapping
  EXPECT_FALSE(can_merge(a, LineSegment(V(65, 10), V(90, 10)), config));      // gap 15
  EXPECT_FALSE(can_merge(a, LineSegment(V(55, 13), V(90, 13)), config));      // parallel, 3 px off
  EXPECT_FALSE(can_merge(a, LineSegment(V(52, 10), V(90, 13.3)), config));     // 5 deg

  std::vector<SupportedSegment> pieces;
  for (double x0 : {0.0, 45.0, 90.0}) {  // three pieces with 5 px gaps
    SupportedSegment s;
    for (double x = x0; x <= x0 + 40; x += 1) s.support.push_back(V(x, 20 + 0.01 * x));
    s.segment = LineSegment(s.support.front(), s.support.back());
    pieces.push_back(s);
  }
  SupportedSegment other;  // crossing line: must stay separate
  other.segment = LineSegment(V(60, 0), V(60, 50));
  pieces.push_back(other);
  EXPECT_EQ(merge_collinear_segments(pieces, config), 2);
  ASSERT_EQ(pieces.size(), 2u);
  const double longest = std::max(pieces[0].segment.length(), pieces[1].segment.length());
  EXPECT_NEAR(longest, std::hypot(130.0, 1.3), 1e-6);
}
