#include <gtest/gtest.h>

#include <random>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "pllvo/common/error.h"
#include "pllvo/features/lines/line_associator.h"
#include "pllvo/features/lines/line_detector.h"
#include "pllvo/features/lines/polygon_scene.h"

using namespace pllvo::lines;
using V = Eigen::Vector2d;

namespace {
// Two keyframes: a polygon scene and its view through a homography, with detected lines,
// LBD descriptors and corner matches (truth + 0.5 px noise, 10% wrong matches).
struct Pair {
  std::vector<LineSegment> a, b;
  cv::Mat da, db;
  std::vector<PointMatch> matches;
  cv::Mat H;
  V map(const V& p) const {
    const cv::Mat q = H * (cv::Mat_<double>(3, 1) << p.x(), p.y(), 1.0);
    return V(q.at<double>(0) / q.at<double>(2), q.at<double>(1) / q.at<double>(2));
  }
  // Ground truth: line a, mapped, lies on line b (direction, offset, overlap).
  bool same(int i, int j) const {
    const LineSegment p(map(a[i].start), map(a[i].end));
    return acute_angle(p, b[j]) < 2.0 * M_PI / 180.0 && std::abs(signed_line_distance(p.midpoint(), b[j])) < 2.0 &&
           point_segment_distance(b[j].midpoint(), p) < 0.5 * b[j].length() + 3.0;
  }
};

Pair make_pair_of_frames(uint64_t seed) {
  PolygonSceneConfig c;
  c.seed = seed;
  const auto scene = render_polygon_scene(c);
  Pair p;
  p.H = (cv::Mat_<double>(3, 3) << 0.98, -0.08, 30, 0.07, 0.99, -12, 2e-5, -1e-5, 1);
  cv::Mat warped;
  cv::warpPerspective(scene.image, warped, p.H, scene.image.size(), cv::INTER_LINEAR, cv::BORDER_REFLECT);
  LineDetector det;
  p.a = det.detect(scene.image);
  p.b = det.detect(warped);
  p.da = compute_lbd_descriptors(scene.image, p.a);
  p.db = compute_lbd_descriptors(warped, p.b);
  std::vector<cv::Point2f> corners;
  cv::goodFeaturesToTrack(scene.image, corners, 300, 0.01, 8);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 0.5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (size_t k = 0; k < corners.size(); ++k) {
    const V a(corners[k].x, corners[k].y);
    const V b = k % 10 == 9 ? V(u(rng) * 752, u(rng) * 480) : p.map(a) + V(noise(rng), noise(rng));
    p.matches.push_back({a, b});
  }
  return p;
}
}  // namespace

TEST(LineAssociator, PointCueWithGeometricCheck) {
  int total = 0, correct = 0, possible = 0;
  for (uint64_t seed : {1, 2, 3}) {
    const Pair p = make_pair_of_frames(seed);
    for (size_t i = 0; i < p.a.size(); ++i)
      for (size_t j = 0; j < p.b.size(); ++j)
        if (p.same(static_cast<int>(i), static_cast<int>(j))) {
          ++possible;
          break;
        }
    LineAssociatorConfig points_only;
    points_only.use_descriptors = false;
    for (const auto& m : LineAssociator(points_only).associate(p.a, p.b, p.matches, p.da, p.db)) {
      EXPECT_EQ(m.cue, AssociationCue::Points);
      EXPECT_GE(m.votes, 2);
      EXPECT_GE(m.descriptor_distance, 0);  // filled in when descriptors are given
      ++total;
      correct += p.same(m.a, m.b);
    }
  }
  ASSERT_GT(total, 0);
  EXPECT_GE(static_cast<double>(correct) / total, 0.97);
  EXPECT_GE(static_cast<double>(correct) / possible, 0.8);
}

TEST(LineAssociator, DescriptorCueAddsCheckedMatches) {
  const Pair p = make_pair_of_frames(4);
  // Point matches that are never near a line: the homography is known, but no line gets votes.
  std::vector<PointMatch> away;
  for (const auto& m : p.matches) {
    bool near = false;
    for (const auto& l : p.a) near = near || point_segment_distance(m.a, l) < 10.0;
    if (!near) away.push_back(m);
  }
  ASSERT_GE(away.size(), 8u);
  const auto matches = LineAssociator().associate(p.a, p.b, away, p.da, p.db);
  int correct = 0;
  for (const auto& m : matches) {
    EXPECT_EQ(m.cue, AssociationCue::Descriptor);
    EXPECT_LE(m.descriptor_distance, LineAssociatorConfig{}.max_descriptor_distance);
    correct += p.same(m.a, m.b);
  }
  EXPECT_GE(matches.size(), 10u);
  EXPECT_GE(static_cast<double>(correct) / matches.size(), 0.9);

  // Without enough matches for the homography nothing can check the descriptor cue: none.
  EXPECT_TRUE(LineAssociator().associate(p.a, p.b, {}, p.da, p.db).empty());
}

TEST(LineAssociator, GeometricCheckRejectsInconsistentVotes) {
  // Lines in A and B, point matches consistent with a pure shift of (10, 0), plus planted
  // votes for a pair that the shift contradicts.
  const std::vector<LineSegment> a = {LineSegment(V(100, 100), V(200, 100)), LineSegment(V(100, 300), V(100, 400))};
  const std::vector<LineSegment> b = {LineSegment(V(110, 100), V(210, 100)), LineSegment(V(400, 50), V(400, 150))};
  std::vector<PointMatch> matches;
  for (int i = 0; i < 6; ++i) {
    matches.push_back({V(100 + 20 * i, 100), V(110 + 20 * i, 100)});  // on line a0 -> b0
    matches.push_back({V(100, 300 + 20 * i), V(400, 50 + 20 * i)});   // wrong: a1 -> b1
  }
  for (int i = 0; i < 10; ++i) matches.push_back({V(300 + 30 * i, 200 + 17 * (i % 3)), V(310 + 30 * i, 200 + 17 * (i % 3))});
  const auto result = LineAssociator().associate(a, b, matches);
  ASSERT_EQ(result.size(), 1u);
  EXPECT_EQ(result[0].a, 0);
  EXPECT_EQ(result[0].b, 0);
  EXPECT_EQ(result[0].descriptor_distance, -1);
  EXPECT_THROW(LineAssociator().associate(a, b, matches, cv::Mat(1, 32, CV_8U), cv::Mat(2, 32, CV_8U)),
               pllvo::InputError);
}
