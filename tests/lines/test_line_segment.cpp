#include <gtest/gtest.h>

#include <cmath>

#include "pllvo/features/lines/line_segment.h"

using pllvo::lines::LineSegment;
using V = Eigen::Vector2d;

TEST(LineSegment, BasicGeometry) {
  const LineSegment s(V(0, 0), V(10, 0));
  EXPECT_DOUBLE_EQ(s.length(), 10.0);
  EXPECT_TRUE(s.direction().isApprox(V(1, 0)));
  EXPECT_TRUE(s.normal().isApprox(V(0, 1)));
  EXPECT_NEAR(pllvo::lines::signed_line_distance(V(3, -2), s), -2.0, 1e-12);
  EXPECT_NEAR(pllvo::lines::point_segment_distance(V(13, 4), s), 5.0, 1e-12);  // to the end point
  EXPECT_NEAR(pllvo::lines::project_along(V(-4, 7), s), -4.0, 1e-12);
  EXPECT_NEAR(LineSegment(V(0, 0), V(-1, -1)).orientation(), M_PI / 4, 1e-12);  // undirected
}

TEST(LineSegment, IntersectionAndDistance) {
  using pllvo::lines::segment_distance;
  using pllvo::lines::segments_intersect;
  const LineSegment a(V(0, 0), V(10, 10)), b(V(0, 10), V(10, 0));
  EXPECT_TRUE(segments_intersect(a, b));
  EXPECT_DOUBLE_EQ(segment_distance(a, b), 0.0);
  const LineSegment c(V(0, 3), V(10, 3)), d(V(12, 0), V(20, 0));
  EXPECT_FALSE(segments_intersect(c, d));
  EXPECT_NEAR(segment_distance(c, d), std::hypot(2.0, 3.0), 1e-12);
  // Collinear touching segments intersect.
  EXPECT_TRUE(segments_intersect(LineSegment(V(0, 0), V(5, 0)), LineSegment(V(5, 0), V(9, 0))));
  EXPECT_NEAR(pllvo::lines::acute_angle(a, c), M_PI / 4, 1e-12);
  EXPECT_NEAR(pllvo::lines::acute_angle(LineSegment(V(0, 0), V(1, 0)), LineSegment(V(0, 0), V(-1, 0.0))), 0.0, 1e-7);
}

TEST(LineSegment, ClipToRectangle) {
  LineSegment s(V(-10, 5), V(30, 5));
  ASSERT_TRUE(pllvo::lines::clip_to_rect(s, V(0, 0), V(20, 20)));
  EXPECT_TRUE(s.start.isApprox(V(0, 5)));
  EXPECT_TRUE(s.end.isApprox(V(20, 5)));
  LineSegment diag(V(-5, -5), V(5, 5));
  ASSERT_TRUE(pllvo::lines::clip_to_rect(diag, V(0, 0), V(20, 20)));
  EXPECT_TRUE(diag.start.isApprox(V(0, 0)));
  LineSegment outside(V(-5, 30), V(30, 30));
  EXPECT_FALSE(pllvo::lines::clip_to_rect(outside, V(0, 0), V(20, 20)));
  EXPECT_TRUE(outside.start.isApprox(V(-5, 30)));  // unchanged
}
