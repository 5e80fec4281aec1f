#include "pllvo/synth/lens.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

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
  // Integer offsets keep the ideal pixel grid aligned with the camera's own K; the margin
  // leaves room for motion blur, which samples the render away from the camera's rays.
  const int ox = static_cast<int>(std::ceil(-xmin)) + 2 + kMaxBlurMargin;
  const int oy = static_cast<int>(std::ceil(-ymin)) + 2 + kMaxBlurMargin;
  view_.fx = k.fx, view_.fy = k.fy, view_.cx = k.cx + ox, view_.cy = k.cy + oy;
  view_.width = static_cast<int>(std::ceil(xmax)) + ox + 3 + kMaxBlurMargin;
  view_.height = static_cast<int>(std::ceil(ymax)) + oy + 3 + kMaxBlurMargin;
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
  view_.drawn = RowRuns::from_mask(needed);
  for (int margin : {2, 4, 6, 8, 12, 16, 24, 32, 40, kMaxBlurMargin}) {
    cv::Mat dilated, ring;
    cv::dilate(needed, dilated, cv::Mat::ones(2 * margin + 1, 2 * margin + 1, CV_8U));
    cv::subtract(dilated, needed, ring);
    blur_regions_.push_back({margin, RowRuns::from_mask(dilated), RowRuns::from_mask(ring)});
  }
  tap_index_.resize(static_cast<size_t>(W) * H);
  tap_fx_.resize(tap_index_.size());
  tap_fy_.resize(tap_index_.size());
  for (int v = 0; v < H; ++v)
    for (int u = 0; u < W; ++u) {
      const cv::Vec2f p = ideal_xy_.at<cv::Vec2f>(v, u);
      const int x0 = static_cast<int>(std::floor(p[0])), y0 = static_cast<int>(std::floor(p[1]));
      if (x0 < 0 || y0 < 0 || x0 + 1 >= view_.width || y0 + 1 >= view_.height)
        throw InternalError("synth: lens map leaves the ideal view");
      const size_t i = static_cast<size_t>(v) * W + u;
      tap_index_[i] = y0 * view_.width + x0;
      tap_fx_[i] = p[0] - static_cast<float>(x0);
      tap_fy_[i] = p[1] - static_cast<float>(y0);
    }
#if defined(__x86_64__) && defined(__GNUC__)
  avx2_ = __builtin_cpu_supports("avx2");
#endif
}

const BlurRegion& LensModel::blur_region(double shift_px) const {
  for (const auto& r : blur_regions_)
    if (r.margin >= shift_px) return r;
  return blur_regions_.back();
}

namespace {

constexpr size_t kPrefetchAhead = 64;  // pixels

inline float lerp4(float p00, float p01, float p10, float p11, float fx, float fy) {
  const float a = p00 + fx * (p01 - p00);
  const float b = p10 + fx * (p11 - p10);
  return a + fy * (b - a);
}

#if defined(__x86_64__) && defined(__GNUC__)
__attribute__((target("avx2"))) void distort_avx2(const float* src, int stride, const int32_t* index,
                                                   const float* fx, const float* fy, float* dst, size_t n) {
  size_t i = 0;
  for (; i + 8 <= n; i += 8) {
    // The taps follow the lens's curves through the ideal image, which the hardware
    // prefetcher does not foresee: ask for the lines a few groups ahead.
    if (i + kPrefetchAhead < n) {
      __builtin_prefetch(src + index[i + kPrefetchAhead]);
      __builtin_prefetch(src + index[i + kPrefetchAhead] + stride);
    }
    // Plain loads: a gather stalls as a whole on any cache miss.
    alignas(32) float t00[8], t01[8], t10[8], t11[8];
    for (int k = 0; k < 8; ++k) {
      const float* q = src + index[i + k];
      t00[k] = q[0], t01[k] = q[1], t10[k] = q[stride], t11[k] = q[stride + 1];
    }
    const __m256 p00 = _mm256_load_ps(t00), p01 = _mm256_load_ps(t01);
    const __m256 p10 = _mm256_load_ps(t10), p11 = _mm256_load_ps(t11);
    const __m256 x = _mm256_loadu_ps(fx + i), y = _mm256_loadu_ps(fy + i);
    const __m256 a = _mm256_add_ps(p00, _mm256_mul_ps(x, _mm256_sub_ps(p01, p00)));
    const __m256 b = _mm256_add_ps(p10, _mm256_mul_ps(x, _mm256_sub_ps(p11, p10)));
    _mm256_storeu_ps(dst + i, _mm256_add_ps(a, _mm256_mul_ps(y, _mm256_sub_ps(b, a))));
  }
  for (; i < n; ++i) {
    const float* p = src + index[i];
    dst[i] = lerp4(p[0], p[1], p[stride], p[stride + 1], fx[i], fy[i]);
  }
}
#endif

}  // namespace

void LensModel::distort(const cv::Mat& ideal, cv::Mat& image) const {
  if (ideal.type() != CV_32F || ideal.rows != view_.height || ideal.cols != view_.width || !ideal.isContinuous())
    throw InternalError("LensModel::distort: expected a continuous CV_32F image of the ideal view's size");
  image.create(ideal_xy_.size(), CV_32F);
  const float* src = ideal.ptr<float>(0);
  float* dst = image.ptr<float>(0);
  const size_t n = tap_index_.size();
#if defined(__x86_64__) && defined(__GNUC__)
  if (avx2_) {
    distort_avx2(src, view_.width, tap_index_.data(), tap_fx_.data(), tap_fy_.data(), dst, n);
    return;
  }
#endif
  for (size_t i = 0; i < n; ++i) {
    const float* p = src + tap_index_[i];
    dst[i] = lerp4(p[0], p[1], p[view_.width], p[view_.width + 1], tap_fx_[i], tap_fy_[i]);
  }
}

}  // namespace pllvo::synth
