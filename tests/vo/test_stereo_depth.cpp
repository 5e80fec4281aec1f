// Metric depth of image points from a rectified pair (stereo_depths): the depth of a textured
// plane at a known distance, the pair's offset taken into account, and the points it must refuse.
#include <cmath>
#include <random>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "pllvo/vo/frame_corners.h"
#include "pllvo/vo/stereo_depth.h"
#include "shifted_pair.h"

namespace pllvo::vo {
namespace {

using testing::shifted;

/// Smoothed random texture: blobs of every orientation, so that the corners are real corners.
cv::Mat texture(int width, int height) {
  cv::Mat noise(height / 4, width / 4, CV_8U);
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> grey(30, 220);
  for (int r = 0; r < noise.rows; ++r)
    for (int c = 0; c < noise.cols; ++c) noise.at<uint8_t>(r, c) = static_cast<uint8_t>(grey(rng));
  cv::Mat image;
  cv::resize(noise, image, cv::Size(width, height), 0, 0, cv::INTER_CUBIC);
  cv::GaussianBlur(image, image, cv::Size(), 1.0);
  return image;
}


struct Rig {
  Pinhole camera{400, 400, 320, 240, 640, 480};
  double baseline = 0.1;
  KltConfig klt;
  PointTracker tracker{klt};
  geometry::StereoTriangulationConfig triangulation;
  StereoRowMatchConfig row;
};

TEST(StereoDepth, GivesTheDepthOfATexturedPlane) {
  Rig rig;
  const double depth = 4.0, disparity = rig.camera.fx * rig.baseline / depth;  // 10 px
  const cv::Mat left = texture(640, 480), right = shifted(left, disparity);
  const auto corners = detect_free_corners(left, {}, 60, 12.0);
  ASSERT_GE(corners.size(), 40u);
  const StereoDepths sd = stereo_depths(rig.tracker, rig.tracker.build_pyramid(left), left, right, corners,
                                        rig.camera, rig.baseline, 0.0, rig.row, rig.triangulation);
  ASSERT_EQ(sd.points.size(), corners.size());
  int measured = 0;
  for (size_t k = 0; k < corners.size(); ++k) {
    if (!sd.points[k]) continue;
    ++measured;
    // 0.1 px of disparity is 1 % of depth here.
    EXPECT_NEAR(sd.points[k]->z(), depth, 0.04) << "corner " << k;
    EXPECT_NEAR(sd.right_px[k].x, corners[k].x - disparity, 0.1);
    const Eigen::Vector2d back = rig.camera.pixel(sd.points[k]->head<2>() / sd.points[k]->z());
    EXPECT_NEAR(back.x(), corners[k].x, 1e-6);
    EXPECT_NEAR(back.y(), corners[k].y, 1e-6);
  }
  EXPECT_EQ(sd.matched, measured);
  EXPECT_GE(measured, static_cast<int>(0.8 * corners.size()));
}

TEST(StereoDepth, TakesThePairsOffsetIntoTheDepth) {
  // A right image whose principal point is off by 1.5 px: the measured disparity is 1.5 px too
  // small; with the offset given, the depth is the true one again, and the match stays as measured.
  Rig rig;
  const double depth = 8.0, disparity = rig.camera.fx * rig.baseline / depth, offset = 1.5;  // 5 px
  const cv::Mat left = texture(640, 480), right = shifted(left, disparity - offset);
  const auto corners = detect_free_corners(left, {}, 40, 12.0);
  const auto pyramid = rig.tracker.build_pyramid(left);
  const StereoDepths plain = stereo_depths(rig.tracker, pyramid, left, right, corners, rig.camera, rig.baseline, 0.0,
                                           rig.row, rig.triangulation);
  const StereoDepths corrected = stereo_depths(rig.tracker, pyramid, left, right, corners, rig.camera, rig.baseline,
                                               offset, rig.row, rig.triangulation);
  int compared = 0;
  for (size_t k = 0; k < corners.size(); ++k) {
    if (!plain.points[k] || !corrected.points[k]) continue;
    ++compared;
    EXPECT_NEAR(plain.points[k]->z(), depth * disparity / (disparity - offset), 0.2);  // 11.4 m
    EXPECT_NEAR(corrected.points[k]->z(), depth, 0.12);
    EXPECT_NEAR(corrected.right_px[k].x, corners[k].x - (disparity - offset), 0.1);
  }
  EXPECT_GE(compared, 30);
}

TEST(StereoDepth, RefusesPointsWithoutAMatchOrADepth) {
  Rig rig;
  const cv::Mat left = texture(640, 480);
  const auto corners = detect_free_corners(left, {}, 40, 12.0);
  // The same image on both sides: no disparity, no depth (below min_disparity_px).
  const StereoDepths none = stereo_depths(rig.tracker, rig.tracker.build_pyramid(left), left, left, corners,
                                          rig.camera, rig.baseline, 0.0, rig.row, rig.triangulation);
  EXPECT_EQ(none.matched, 0);
  EXPECT_GE(none.depth_rejects, static_cast<int>(corners.size()) / 2);
  for (const auto& p : none.points) EXPECT_FALSE(p.has_value());
  // No right image: nothing, and no error.
  const StereoDepths empty = stereo_depths(rig.tracker, rig.tracker.build_pyramid(left), left, cv::Mat(), corners,
                                           rig.camera, rig.baseline, 0.0, rig.row, rig.triangulation);
  EXPECT_EQ(empty.points.size(), corners.size());
  EXPECT_EQ(empty.matched, 0);
}

TEST(StereoDepth, ReadsADepthImageAndRefusesItsEdges) {
  cv::Mat depth(100, 100, CV_32F, cv::Scalar(2.0f));
  depth(cv::Rect(50, 0, 50, 100)).setTo(3.0f);  // a step: pixels next to it are on an edge
  depth.at<float>(10, 10) = 0.0f;                // no return
  const DepthConfig config;
  EXPECT_FLOAT_EQ(depth_at(depth, {20.0f, 20.0f}, config), 2.0f);
  EXPECT_FLOAT_EQ(depth_at(depth, {80.2f, 20.0f}, config), 3.0f);
  EXPECT_TRUE(std::isnan(depth_at(depth, {49.6f, 20.0f}, config)));
  EXPECT_EQ(depth_at(depth, {10.0f, 10.0f}, config), 0.0f);
  EXPECT_EQ(depth_at(depth, {-3.0f, 10.0f}, config), 0.0f);
  EXPECT_EQ(depth_at(depth, {20.0f, 120.0f}, config), 0.0f);
}

TEST(StereoDepth, DepthImagePointsSitAtTheirDepthAsAVirtualPair) {
  const Pinhole camera{400, 400, 50, 50, 100, 100};
  const double baseline = 0.08;
  cv::Mat depth(100, 100, CV_32F, cv::Scalar(2.0f));
  depth(cv::Rect(50, 0, 50, 100)).setTo(3.0f);
  const std::vector<cv::Point2f> points{{20.0f, 30.0f}, {80.0f, 60.0f}, {49.6f, 20.0f}, {-5.0f, 20.0f}};
  const StereoDepths sd = depth_image_depths(depth, points, camera, baseline, DepthConfig{}, {});
  ASSERT_TRUE(sd.points[0] && sd.points[1]);
  EXPECT_NEAR(sd.points[0]->z(), 2.0, 1e-5);
  EXPECT_NEAR(sd.points[1]->z(), 3.0, 1e-5);
  EXPECT_NEAR(sd.points[0]->x(), (20.0 - 50.0) / 400.0 * 2.0, 1e-6);
  EXPECT_NEAR(sd.right_px[0].x, 20.0 - 400.0 * baseline / 2.0, 1e-4);  // 16 px of virtual disparity
  EXPECT_FALSE(sd.points[2].has_value());  // on the step: a depth edge
  EXPECT_FALSE(sd.points[3].has_value());  // outside the image: no measurement
  EXPECT_EQ(sd.edge_rejects, 1);
  EXPECT_EQ(sd.matched, 2);
  EXPECT_TRUE(std::isnan(sd.right_px[2].x));
  const StereoDepths none = depth_image_depths(cv::Mat(), points, camera, baseline, DepthConfig{}, {});
  EXPECT_EQ(none.points.size(), points.size());
  EXPECT_EQ(none.matched, 0);
}

}  // namespace
}  // namespace pllvo::vo
