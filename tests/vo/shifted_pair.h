#pragma once
// A rectified stereo pair of a fronto-parallel scene for the stereo matching tests.
#include <opencv2/imgproc.hpp>

namespace pllvo::vo::testing {

/// The right image of a rectified pair: the left one moved left by `disparity` pixels.
inline cv::Mat shifted(const cv::Mat& left, double disparity) {
  cv::Mat right;
  const cv::Mat m = (cv::Mat_<double>(2, 3) << 1, 0, -disparity, 0, 1, 0);
  cv::warpAffine(left, right, m, left.size(), cv::INTER_CUBIC, cv::BORDER_REPLICATE);
  return right;
}

}  // namespace pllvo::vo::testing
