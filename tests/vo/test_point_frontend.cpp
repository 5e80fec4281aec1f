#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "pllvo/common/error.h"
#include "pllvo/vo/point_frontend.h"

namespace pllvo::vo {
namespace {

cv::Mat checkerboard_with_noise(cv::Size size) {
  cv::Mat img(size, CV_8UC1);
  cv::RNG rng(7);
  for (int y = 0; y < size.height; ++y)
    for (int x = 0; x < size.width; ++x)
      img.at<unsigned char>(y, x) = static_cast<unsigned char>(((x / 16 + y / 16) % 2 ? 180 : 60) + rng.uniform(-20, 20));
  cv::GaussianBlur(img, img, cv::Size(3, 3), 0);
  return img;
}

class Frontends : public ::testing::TestWithParam<std::string> {};

TEST_P(Frontends, DetectsAtMostTheBudgetSpreadOverTheImage) {
  FrontendConfig config;
  config.type = GetParam();
  config.max_points = 200;
  auto frontend = make_point_frontend(config);
  EXPECT_EQ(frontend->name(), GetParam());
  const cv::Mat img = checkerboard_with_noise({640, 480});
  const PointFeatures f = frontend->detect(img);
  ASSERT_GE(f.size(), 150u);
  EXPECT_LE(f.size(), 200u);
  EXPECT_EQ(f.descriptors.rows, static_cast<int>(f.size()));
  EXPECT_EQ(f.scores.size(), f.size());
  EXPECT_TRUE(f.binary());
  // Every quadrant gets a fair share.
  int quadrant[4] = {0, 0, 0, 0};
  for (const auto& p : f.points) quadrant[(p.x >= 320) + 2 * (p.y >= 240)]++;
  for (int q : quadrant) EXPECT_GE(q, static_cast<int>(f.size()) / 8);
}

TEST_P(Frontends, DescribesTrackedPointsWhereTheyAreAndDetectsAwayFromThem) {
  FrontendConfig config;
  config.type = GetParam();
  config.min_distance_px = 15;
  config.max_points = 100;
  auto frontend = make_point_frontend(config);
  const cv::Mat img = checkerboard_with_noise({640, 480});
  // The second point is too close to the border for a descriptor patch.
  const std::vector<cv::Point2f> tracked = {{320.5f, 240.25f}, {3.f, 100.f}, {100.f, 100.f}, {500.f, 400.f}};
  const PointFeatures f = frontend->detect(img, tracked);
  ASSERT_EQ(f.source.size(), f.size());
  ASSERT_EQ(f.descriptors.rows, static_cast<int>(f.size()));
  std::vector<int> described;
  for (size_t i = 0; i < f.size(); ++i) {
    if (f.source[i] < 0) continue;
    described.push_back(f.source[i]);
    EXPECT_EQ(f.points[i], tracked[f.source[i]]);
  }
  EXPECT_EQ(described, (std::vector<int>{0, 2, 3}));
  const size_t fresh = f.size() - described.size();
  EXPECT_GE(fresh, 80u);
  EXPECT_LE(f.size(), 100u);
  for (size_t i = 0; i < f.size(); ++i) {
    if (f.source[i] >= 0) continue;
    for (const auto& o : tracked) EXPECT_GE(cv::norm(f.points[i] - o), 14.0);
  }
  // A tracked point is described the same way each time.
  const PointFeatures g = frontend->detect(img, tracked);
  ASSERT_EQ(g.source[0], 0);
  EXPECT_EQ(cv::norm(g.descriptors.row(0), f.descriptors.row(0), cv::NORM_HAMMING), 0.0);
  if (GetParam() == "shitomasi") {
    // Single-scale detection: a fresh corner, once tracked, keeps its descriptor.
    const PointFeatures h = frontend->detect(img, {f.points[f.size() - 1]});
    ASSERT_EQ(h.source[0], 0);
    EXPECT_EQ(cv::norm(h.descriptors.row(0), f.descriptors.row(f.size() - 1), cv::NORM_HAMMING), 0.0);
  }
}

TEST_P(Frontends, BlankAndBlackImagesGiveNoPoints) {
  FrontendConfig config;
  config.type = GetParam();
  auto frontend = make_point_frontend(config);
  EXPECT_TRUE(frontend->detect(cv::Mat(480, 640, CV_8UC1, cv::Scalar(0))).empty());
  EXPECT_TRUE(frontend->detect(cv::Mat(480, 640, CV_8UC1, cv::Scalar(200))).empty());
  // Tiny images (smaller than a descriptor patch) are not an error either.
  EXPECT_TRUE(frontend->detect(checkerboard_with_noise({20, 20})).empty());
}

INSTANTIATE_TEST_SUITE_P(Vo, Frontends, ::testing::Values("orb", "shitomasi"));

TEST(PointFrontend, UnknownNameIsAnInputError) {
  FrontendConfig config;
  config.type = "sift";
  EXPECT_THROW(make_point_frontend(config), InputError);
}

TEST(SelectOnGrid, GivesEachCellItsShareBeforeTheStrongestRest) {
  // 10 strong points in the left cell, 2 weak in the right one; budget 6 over a 2x1 grid.
  std::vector<cv::Point2f> pts;
  std::vector<float> scores;
  for (int i = 0; i < 10; ++i) pts.emplace_back(10.f + i, 10.f), scores.push_back(100.f + i);
  pts.emplace_back(90.f, 10.f), scores.push_back(1.f);
  pts.emplace_back(95.f, 10.f), scores.push_back(2.f);
  const auto sel = select_on_grid(pts, scores, {100, 20}, 2, 1, 6);
  ASSERT_EQ(sel.size(), 6u);
  int right = 0;
  for (size_t i : sel) right += pts[i].x > 50;
  EXPECT_EQ(right, 2);
  // The four left ones are the strongest of their cell.
  for (size_t i : sel)
    if (pts[i].x < 50) EXPECT_GE(scores[i], 106.f);
}

}  // namespace
}  // namespace pllvo::vo
