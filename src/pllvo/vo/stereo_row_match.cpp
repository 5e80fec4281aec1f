#include "pllvo/vo/stereo_row_match.h"

#include <cmath>

#include <opencv2/imgproc.hpp>

namespace pllvo::vo {

std::optional<float> refine_along_row(const cv::Mat& left, const cv::Mat& right, const cv::Point2f& left_px,
                                      float right_x, const StereoRowMatchConfig& config) {
  const int w = config.window_px, half = w / 2;
  const auto inside = [&](const cv::Mat& image, float x, float y) {
    return x - half - 1 >= 0 && y - half - 1 >= 0 && x + half + 1 < image.cols - 1 && y + half + 1 < image.rows - 1;
  };
  if (!inside(left, left_px.x, left_px.y) || !inside(right, right_x, left_px.y)) return std::nullopt;

  // Template with a one-pixel margin for central differences.
  cv::Mat t;
  cv::getRectSubPix(left, cv::Size(w + 2, w + 2), left_px, t, CV_32F);
  cv::Mat tx(w, w, CV_32F), tmpl = t(cv::Rect(1, 1, w, w)).clone();
  double gxx = 0, gyy = 0;
  for (int r = 0; r < w; ++r)
    for (int c = 0; c < w; ++c) {
      const float dx = 0.5f * (t.at<float>(r + 1, c + 2) - t.at<float>(r + 1, c));
      const float dy = 0.5f * (t.at<float>(r + 2, c + 1) - t.at<float>(r, c + 1));
      tx.at<float>(r, c) = dx;
      gxx += dx * dx, gyy += dy * dy;
    }
  if (gxx <= 0 || gxx < config.min_horizontal_share * (gxx + gyy)) return std::nullopt;

  // Inverse-compositional Gauss-Newton on x alone, with the template's own gradient.
  const float x0 = right_x;
  float x = right_x;
  const float tmean = static_cast<float>(cv::mean(tmpl)[0]);
  cv::Mat patch;
  for (int it = 0; it < config.max_iterations; ++it) {
    if (!inside(right, x, left_px.y)) return std::nullopt;
    cv::getRectSubPix(right, cv::Size(w, w), cv::Point2f(x, left_px.y), patch, CV_32F);
    const float offset = static_cast<float>(cv::mean(patch)[0]) - tmean;  // brightness difference of the cameras
    double num = 0;
    for (int r = 0; r < w; ++r)
      for (int c = 0; c < w; ++c) num += tx.at<float>(r, c) * (patch.at<float>(r, c) - offset - tmpl.at<float>(r, c));
    const double step = num / gxx;
    x -= static_cast<float>(step);
    if (std::abs(x - x0) > config.max_shift_px) return std::nullopt;
    if (std::abs(step) < 0.01) return x;
  }
  return std::nullopt;
}

}  // namespace pllvo::vo
