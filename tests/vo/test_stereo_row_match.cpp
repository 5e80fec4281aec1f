// 1-D stereo refinement along the row: exact disparities of shifted synthetic images, and the
// near-horizontal edges it must refuse.
#include <cmath>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "pllvo/vo/stereo_row_match.h"
#include "shifted_pair.h"

namespace pllvo::vo {
namespace {

using testing::shifted;

/// A smooth step edge through (cx, cy) at `angle_deg` from the horizontal, dark below, bright above,
/// plus (optionally) a blob so that the window has texture in both directions.
cv::Mat edge_image(double angle_deg, double cx, double cy, bool blob) {
  cv::Mat img(240, 320, CV_8U);
  const double a = angle_deg * M_PI / 180.0, nx = -std::sin(a), ny = std::cos(a);
  for (int r = 0; r < img.rows; ++r)
    for (int c = 0; c < img.cols; ++c) {
      const double d = (c - cx) * nx + (r - cy) * ny;  // signed distance to the edge
      double v = 80 + 90 / (1 + std::exp(d / 1.2));
      if (blob) v += 60 * std::exp(-((c - cx - 4) * (c - cx - 4) + (r - cy + 3) * (r - cy + 3)) / 18.0);
      img.at<uint8_t>(r, c) = cv::saturate_cast<uint8_t>(v);
    }
  return img;
}


TEST(StereoRowMatch, RecoversTheDisparityOfATexturedPoint) {
  const cv::Mat left = edge_image(60, 160, 120, true);
  const double d = 17.3;
  const cv::Mat right = shifted(left, d);
  const cv::Point2f p(160, 120);
  for (float start : {-2.0f, -0.6f, 0.0f, 0.9f, 2.2f}) {
    const auto x = refine_along_row(left, right, p, static_cast<float>(p.x - d) + start);
    ASSERT_TRUE(x.has_value()) << "start offset " << start;
    EXPECT_NEAR(*x, p.x - d, 0.08) << "start offset " << start;  // bilinear resampling of 8-bit images
  }
}

TEST(StereoRowMatch, CorrectsASlideAlongASlantedEdge) {
  // 2-D LK on an edge can land anywhere along it: 0.8 px off in y on a 25 deg edge is
  // 0.8 / tan(25 deg) = 1.7 px off in x. Along the row, x is fixed again.
  const cv::Mat left = edge_image(25, 160, 120, false);
  const double d = 12.0;
  const cv::Mat right = shifted(left, d);
  const cv::Point2f p(160, 120);
  const float slid = static_cast<float>(p.x - d + 0.8 / std::tan(25 * M_PI / 180));
  const auto x = refine_along_row(left, right, p, slid);
  ASSERT_TRUE(x.has_value());
  EXPECT_NEAR(*x, p.x - d, 0.1);
}

TEST(StereoRowMatch, RefusesNearHorizontalEdgesAndTheBorder) {
  const cv::Mat left = edge_image(4, 160, 120, false);  // horizontal share sin^2(4 deg) = 0.005
  const cv::Mat right = shifted(left, 10);
  EXPECT_FALSE(refine_along_row(left, right, {160, 120}, 150).has_value());
  const cv::Mat textured = edge_image(60, 160, 120, true);
  EXPECT_FALSE(refine_along_row(textured, shifted(textured, 10), {5, 120}, 2).has_value());
}

TEST(StereoRowMatch, GivesUpWhenTheMatchIsFartherThanTheLimit) {
  const cv::Mat left = edge_image(60, 160, 120, true);
  const cv::Mat right = shifted(left, 17.3);
  StereoRowMatchConfig c;
  c.max_shift_px = 1.0;
  EXPECT_FALSE(refine_along_row(left, right, {160, 120}, 160 - 17.3f + 2.5f, c).has_value());
}

}  // namespace
}  // namespace pllvo::vo
