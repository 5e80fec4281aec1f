#include "pllvo/synth/lens.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "pllvo/common/error.h"

namespace pllvo::synth {

LensModel::LensModel(const camera::CameraModel& camera) {
  const int W = camera.width(), H = camera.height();
  const auto& k = camera.intrinsics();
  bearings_.create(H, W, CV_32FC3);
  cv::Mat undistorted(H, W, CV_64FC2);  // in the camera's own K, before the ideal offset
  double xmin = 1e300, xmax = -1e300, ymin = 1e300, ymax = -1e300;
  for (int v = 0; v < H; ++v)
    for (int u = 0; u < W; ++u) {
      Eigen::Vector3d b;
      if (!camera.unproject(Eigen::Vector2d(u, v), b) || b.z() <= 1e-3)
        throw InternalError("synth: the camera model cannot be inverted at pixel (" + std::to_string(u) + ", " +
                            std::to_string(v) + ")");
      bearings_.at<cv::Vec3f>(v, u) = cv::Vec3f(static_cast<float>(b.x()), static_cast<float>(b.y()),
                                                static_cast<float>(b.z()));
      const double x = k.fx * b.x() / b.z() + k.cx, y = k.fy * b.y() / b.z() + k.cy;
      undistorted.at<cv::Vec2d>(v, u) = cv::Vec2d(x, y);
      xmin = std::min(xmin, x), xmax = std::max(xmax, x);
      ymin = std::min(ymin, y), ymax = std::max(ymax, y);
    }
  // Integer offsets keep the ideal pixel grid aligned with the camera's own K.
  const int ox = static_cast<int>(std::ceil(-xmin)) + 2, oy = static_cast<int>(std::ceil(-ymin)) + 2;
  view_.fx = k.fx, view_.fy = k.fy, view_.cx = k.cx + ox, view_.cy = k.cy + oy;
  view_.width = static_cast<int>(std::ceil(xmax)) + ox + 3;
  view_.height = static_cast<int>(std::ceil(ymax)) + oy + 3;
  cv::Mat needed = cv::Mat::zeros(view_.height, view_.width, CV_8U);
  ideal_xy_.create(H, W, CV_32FC2);
  for (int v = 0; v < H; ++v)
    for (int u = 0; u < W; ++u) {
      const cv::Vec2d p = undistorted.at<cv::Vec2d>(v, u);
      const double x = p[0] + ox, y = p[1] + oy;
      ideal_xy_.at<cv::Vec2f>(v, u) = cv::Vec2f(static_cast<float>(x), static_cast<float>(y));
      // Bilinear sampling reads the 2x2 neighbourhood; one more pixel of slack on each side.
      const int x0 = static_cast<int>(std::floor(x)) - 1, y0 = static_cast<int>(std::floor(y)) - 1;
      for (int r = std::max(0, y0); r <= std::min(view_.height - 1, y0 + 3); ++r)
        for (int c = std::max(0, x0); c <= std::min(view_.width - 1, x0 + 3); ++c) needed.at<uint8_t>(r, c) = 1;
    }
  view_.row_begin.assign(view_.height, 0);
  view_.row_end.assign(view_.height, 0);
  view_.hole_begin.assign(view_.height, 0);
  view_.hole_end.assign(view_.height, 0);
  for (int r = 0; r < view_.height; ++r) {
    const auto* m = needed.ptr<uint8_t>(r);
    int first = -1, last = -1, gap_begin = 0, gap_end = 0;
    for (int c = 0; c < view_.width; ++c) {
      if (!m[c]) continue;
      if (first < 0) first = c;
      if (last >= 0 && c - last - 1 > gap_end - gap_begin) gap_begin = last + 1, gap_end = c;
      last = c;
    }
    if (first < 0) continue;
    view_.row_begin[r] = first;
    view_.row_end[r] = last + 1;
    view_.hole_begin[r] = gap_begin;
    view_.hole_end[r] = gap_end;
  }
  cv::convertMaps(ideal_xy_, cv::Mat(), map_fixed_, map_frac_, CV_16SC2);
}

void LensModel::distort(const cv::Mat& ideal, cv::Mat& image) const {
  cv::remap(ideal, image, map_fixed_, map_frac_, cv::INTER_LINEAR, cv::BORDER_CONSTANT);
}

}  // namespace pllvo::synth
