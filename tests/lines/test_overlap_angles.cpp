#include <gtest/gtest.h>

#include <cmath>

#include "pllvo/features/lines/overlap_angles.h"

using namespace pllvo::lines;
using V = Eigen::Vector2d;

namespace {
// Two families of 4 parallel lines crossing at `angle_deg`, every line crossing every other
// family's line: 16 overlaps at that angle.
std::vector<LineSegment> lattice(double angle_deg, V origin = V(200, 200)) {
  std::vector<LineSegment> lines;
  const double a = angle_deg * M_PI / 180.0;
  const V d1(1, 0), d2(std::cos(a), std::sin(a));
  const V n1(0, 1), n2(-d2.y(), d2.x());
  for (int i = -2; i < 2; ++i) {
    lines.emplace_back(origin + 25.0 * i * n1 - 150 * d1, origin + 25.0 * i * n1 + 150 * d1);
    lines.emplace_back(origin + 25.0 * i * n2 - 150 * d2, origin + 25.0 * i * n2 + 150 * d2);
  }
  return lines;
}
}  // namespace

TEST(OverlapAngles, SetOfALattice) {
  const auto set = overlap_angle_set(lattice(65.0));
  ASSERT_EQ(set.size(), 16u);
  for (double a : set.angles_deg) EXPECT_NEAR(a, 65.0, 1e-9);
  ASSERT_EQ(set.histogram.size(), 9u);
  EXPECT_DOUBLE_EQ(set.histogram[6], 1.0);  // [60, 70)
}

TEST(OverlapAngles, DistanceIsEarthMoversInDegrees) {
  const auto a = overlap_angle_set(lattice(60.0));
  const auto moved = overlap_angle_set(lattice(60.0, V(260, 230)));  // same structure elsewhere
  EXPECT_NEAR(overlap_angle_distance(a, moved), 0.0, 1e-9);
  const auto b = overlap_angle_set(lattice(85.0));
  EXPECT_NEAR(overlap_angle_distance(a, b), 25.0, 1e-9);
  EXPECT_NEAR(overlap_angle_distance(b, a), 25.0, 1e-9);

  // Mixed sets: {10, 50} vs {10, 10, 50, 90}: the quantile functions agree on [0, 0.75) and
  // differ by 40 deg on [0.75, 1] -> 10.
  OverlapAngleSet x, y;
  x.angles_deg = {10, 50};
  y.angles_deg = {10, 10, 50, 90};
  EXPECT_NEAR(overlap_angle_distance(x, y), 10.0, 1e-9);

  const OverlapAngleSet empty;
  EXPECT_EQ(overlap_angle_distance(empty, empty), 0.0);
  EXPECT_EQ(overlap_angle_distance(a, empty), 90.0);
}
