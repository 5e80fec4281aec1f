#include <gtest/gtest.h>

#include <cmath>

#include "pllvo/features/lines/cross_constraint.h"
#include "pllvo/features/lines/line_overlaps.h"

using namespace pllvo::lines;
using V = Eigen::Vector2d;

namespace {
// A regular grid: 6 horizontal and 6 vertical lines crossing at right angles.
std::vector<LineSegment> grid() {
  std::vector<LineSegment> g;
  for (int i = 0; i < 6; ++i) {
    g.emplace_back(V(100, 100 + 40 * i), V(320, 100 + 40 * i), static_cast<int>(g.size()));
    g.emplace_back(V(110 + 40 * i, 90), V(110 + 40 * i, 310), static_cast<int>(g.size()));
  }
  return g;
}

// A planted cluster: 6 nearly parallel segments (0..10 deg) crossing each other in one spot.
std::vector<LineSegment> cluster(int first_id) {
  std::vector<LineSegment> c;
  const V centre(500, 200);
  for (int i = 0; i < 6; ++i) {
    const double a = (2.0 * i) * M_PI / 180.0;
    const V d(std::cos(a), std::sin(a));
    c.emplace_back(centre - 40 * d + V(0, 0.3 * i), centre + 40 * d, first_id + i);
  }
  return c;
}
}  // namespace

TEST(LineOverlaps, DefinitionIntersectOrWithinDistance) {
  const std::vector<LineSegment> lines = {
      LineSegment(V(0, 0), V(100, 0)),      // 0
      LineSegment(V(50, -20), V(50, 20)),   // 1: crosses 0 at 90 deg
      LineSegment(V(101.5, 0), V(150, 0)),  // 2: 1.5 px past the end of 0, collinear
      LineSegment(V(0, 3), V(100, 3)),      // 3: parallel to 0, 3 px away: no overlap
      LineSegment(V(0, 40), V(100, 48)),    // 4: far away
  };
  const auto overlaps = find_overlaps(lines, 2.0);
  std::vector<std::pair<int, int>> pairs;
  for (const auto& o : overlaps) pairs.emplace_back(o.a, o.b);
  EXPECT_EQ(pairs, (std::vector<std::pair<int, int>>{{0, 1}, {0, 2}, {1, 3}}));
  EXPECT_NEAR(overlaps[0].angle_rad, M_PI / 2, 1e-12);
  EXPECT_NEAR(overlaps[1].angle_rad, 0.0, 1e-6);
}

TEST(CrossConstraint, RemovesPlantedClusterKeepsGrid) {
  auto lines = grid();
  const auto planted = cluster(100);
  lines.insert(lines.end(), planted.begin(), planted.end());
  std::vector<uint8_t> removed;
  const auto kept = apply_cross_constraint(lines, {}, &removed);
  ASSERT_EQ(removed.size(), lines.size());
  for (size_t i = 0; i < lines.size(); ++i) EXPECT_EQ(removed[i], lines[i].id >= 100 ? 1 : 0) << "line " << lines[i].id;
  EXPECT_EQ(kept.size(), grid().size());
  for (const auto& k : kept) EXPECT_LT(k.id, 100);
}

TEST(CrossConstraint, MoreThanTwoShallowOverlapsAreNeeded) {
  // Two near-parallel neighbours (a thin bar and a continuation) are allowed; a third is not.
  const LineSegment base(V(0, 0), V(100, 0), 0);
  std::vector<LineSegment> lines = {base, LineSegment(V(0, 1.5), V(100, 1.8), 1), LineSegment(V(99, 0.5), V(180, 3), 2)};
  EXPECT_EQ(apply_cross_constraint(lines, {}).size(), 3u);
  lines.emplace_back(V(20, -2), V(80, -1), 3);  // 1 px from the base line only
  const auto kept = apply_cross_constraint(lines, {});
  EXPECT_EQ(kept.size(), 3u);  // the base line, with 3 shallow overlaps, goes
  for (const auto& k : kept) EXPECT_NE(k.id, 0);
  CrossConstraintConfig off;
  off.enabled = false;
  EXPECT_EQ(apply_cross_constraint(lines, off).size(), 4u);
}
