#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <random>

#include "pllvo/common/error.h"
#include "pllvo/common/yaml_config.h"
#include "pllvo/features/lines/stereo_line_matcher.h"

using namespace pllvo::lines;
using V = Eigen::Vector2d;
using V3 = Eigen::Vector3d;

namespace {
// A rectified pair with EuRoC-like intrinsics; the right camera 0.11 m to the right.
constexpr double kF = 460.0, kCx = 376.0, kCy = 240.0, kBaseline = 0.11;

V project(const V3& p, double camera_x) { return {kF * (p.x() - camera_x) / p.z() + kCx, kF * p.y() / p.z() + kCy}; }

struct StereoLines {
  std::vector<LineSegment> left, right;
  std::vector<int> truth;  // right index per left line
};

// Random 3-D segments 1.5-6 m in front of the pair, at least 20 deg from horizontal in the
// image; the right list is shuffled.
StereoLines random_lines(int n, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> x(-1.5, 1.5), z(1.5, 6.0), u(-1.0, 1.0);
  StereoLines s;
  while (static_cast<int>(s.left.size()) < n) {
    const V3 a(x(rng), x(rng), z(rng));
    const V3 b = a + 0.8 * V3(u(rng), u(rng), 0.5 * u(rng));
    if (b.z() < 1.0) continue;
    const LineSegment l(project(a, 0), project(b, 0)), r(project(a, kBaseline), project(b, kBaseline));
    const V d = l.end - l.start;
    if (l.length() < 30 || std::atan2(std::abs(d.y()), std::abs(d.x())) < 20 * M_PI / 180) continue;
    s.left.push_back(l);
    s.right.push_back(r);
  }
  std::vector<int> order(n);
  for (int i = 0; i < n; ++i) order[i] = i;
  std::shuffle(order.begin(), order.end(), rng);
  std::vector<LineSegment> shuffled(n);
  s.truth.assign(n, -1);
  for (int k = 0; k < n; ++k) shuffled[k] = s.right[order[k]], s.truth[order[k]] = k;
  s.right = shuffled;
  return s;
}
}  // namespace

TEST(StereoLineMatcher, DisparityAtRowIsTheHorizontalShiftOfTheTwoLines) {
  const LineSegment left(V(100, 50), V(120, 250)), right(V(80, 50), V(96, 250));
  EXPECT_NEAR(disparity_at_row(left, right, 50), 20.0, 1e-12);
  EXPECT_NEAR(disparity_at_row(left, right, 250), 24.0, 1e-12);
  EXPECT_NEAR(disparity_at_row(left, right, 150), 22.0, 1e-12);  // linear along the rows
}

TEST(StereoLineMatcher, MatchesProjectedLinesWithoutDescriptorsAndNeverWrongly) {
  int matched = 0, total = 0;
  for (uint64_t seed = 1; seed <= 5; ++seed) {
    const StereoLines s = random_lines(12, seed);
    const auto matches = match_stereo_lines(s.left, s.right, {}, {}, StereoLineMatcherConfig{});
    for (const auto& m : matches) EXPECT_EQ(m.b, s.truth[m.a]) << "seed " << seed << " left line " << m.a;
    matched += static_cast<int>(matches.size());
    total += static_cast<int>(s.left.size());
  }
  // Unmatched lines are the ambiguous ones (another right line with the same rows, angle and
  // a valid disparity); random lines in a 3 m wide volume leave few of them (59 of 60 matched).
  EXPECT_GE(matched, total * 85 / 100) << matched << " of " << total;
}

TEST(StereoLineMatcher, SkipsFlatLinesNegativeDisparityAndAmbiguousPairs) {
  const StereoLineMatcherConfig c;
  // Nearly horizontal: its rows do not fix the disparity.
  const LineSegment flat_l(V(100, 100), V(300, 130)), flat_r(V(80, 100), V(280, 130));
  EXPECT_TRUE(match_stereo_lines({flat_l}, {flat_r}, {}, {}, c).empty());
  // The right line to the right of the left one: behind the cameras.
  const LineSegment l(V(200, 100), V(210, 300)), behind(V(230, 100), V(240, 300));
  EXPECT_TRUE(match_stereo_lines({l}, {behind}, {}, {}, c).empty());
  // Too few shared rows.
  const LineSegment high(V(190, 20), V(195, 120));
  EXPECT_TRUE(match_stereo_lines({l}, {high}, {}, {}, c).empty());
  // Two parallel candidates, no descriptor to decide: no match; the nearer one alone: a match.
  const LineSegment r1(V(185, 100), V(195, 300)), r2(V(170, 100), V(180, 300));
  EXPECT_TRUE(match_stereo_lines({l}, {r1, r2}, {}, {}, c).empty());
  const auto one = match_stereo_lines({l}, {r1}, {}, {}, c);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one[0].a, 0);
  EXPECT_EQ(one[0].b, 0);
}

TEST(StereoLineMatcher, DescriptorsDecideBetweenGeometricCandidates) {
  const LineSegment l(V(200, 100), V(210, 300)), r1(V(185, 100), V(195, 300)), r2(V(170, 100), V(180, 300));
  cv::Mat dl = cv::Mat::zeros(1, 32, CV_8U), dr = cv::Mat::zeros(2, 32, CV_8U);
  dr.row(0).setTo(0xFF);  // 256 bits apart from the left line
  dr.at<uchar>(1, 0) = 0x0F;  // 4 bits apart
  const auto m = match_stereo_lines({l}, {r1, r2}, dl, dr, StereoLineMatcherConfig{});
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m[0].b, 1);
  EXPECT_EQ(m[0].descriptor_distance, 4);
  EXPECT_THROW(match_stereo_lines({l}, {r1, r2}, dl, dr.row(0), StereoLineMatcherConfig{}), pllvo::InputError);
}
