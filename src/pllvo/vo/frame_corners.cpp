#include "pllvo/vo/frame_corners.h"

#include <opencv2/imgproc.hpp>

namespace pllvo::vo {

std::vector<cv::Point2f> detect_free_corners(const cv::Mat& image, const std::vector<cv::Point2f>& occupied,
                                             int max_new, double spacing_px) {
  std::vector<cv::Point2f> corners;
  if (image.empty() || max_new <= 0) return corners;
  // Shi-Tomasi's quality is relative to the frame's strongest corner, so a dark frame still
  // gives its best; the border keeps KLT's window inside the image.
  const int border = static_cast<int>(spacing_px);
  cv::Mat mask = cv::Mat::zeros(image.size(), CV_8U);
  if (image.cols <= 2 * border || image.rows <= 2 * border) return corners;
  mask(cv::Rect(border, border, image.cols - 2 * border, image.rows - 2 * border)).setTo(255);
  for (const auto& p : occupied) cv::circle(mask, p, static_cast<int>(spacing_px), cv::Scalar(0), cv::FILLED);
  constexpr double kQuality = 0.01;
  cv::goodFeaturesToTrack(image, corners, max_new, kQuality, spacing_px, mask);
  return corners;
}

}  // namespace pllvo::vo
