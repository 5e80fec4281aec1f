#include "pllvo/synth/flow_blur.h"

#include <algorithm>
#include <cmath>

#include "pllvo/common/error.h"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define PLLVO_FLOW_BLUR_AVX2 1
#endif

namespace pllvo::synth {

// Pixels are processed in groups of 8 that share one sample count (the longest path among
// them; neighbours move alike). The AVX2 path performs the same single-precision operations
// in the same order as the scalar one (no FMA), so both give identical images.
struct FlowBlur::Pass {
  const float* radiance;
  const float* inv_depth;
  int stride;
  float xmax, ymax;  // largest top-left tap coordinate
  float r0[9], t0[3], r1[9], t1[3];  // render frame -> start / end frame (rotation row-major)
  float fx, fy, cx, cy, ifx, ify;
  float margin;  // largest displacement per axis: the render is valid that far out
  float inv_step;
  int max_samples;
  float weight;
  bool add;
};

namespace {

constexpr int kGroup = 8;
constexpr int kChunk = 512;  // pixels whose paths are computed before their samples
constexpr size_t kPrefetchAhead = 64;  // pixels
// Scaled depth (z / z_render) below which a point is treated as passing the camera: its
// pixel is left unblurred (a point that close to the camera plane only occurs at the near plane).
constexpr float kMinScaledZ = 1e-4f;

/// Displacement of the scene point behind one pixel at the start and end of the sub-exposure.
inline void displacement(const FlowBlur::Pass& p, float x, float y, float d[4]) {
  // The pixel's ray (rx, ry, 1) and the inverse depth of the render's nearest pixel.
  const float rx = (x - p.cx) * p.ifx, ry = (y - p.cy) * p.ify;
  const float w = p.inv_depth[static_cast<int>(std::nearbyint(y)) * p.stride + static_cast<int>(std::nearbyint(x))];
  const float ax = p.r0[0] * rx + p.r0[1] * ry + p.r0[2] + w * p.t0[0];
  const float ay = p.r0[3] * rx + p.r0[4] * ry + p.r0[5] + w * p.t0[1];
  const float az = p.r0[6] * rx + p.r0[7] * ry + p.r0[8] + w * p.t0[2];
  const float bx = p.r1[0] * rx + p.r1[1] * ry + p.r1[2] + w * p.t1[0];
  const float by = p.r1[3] * rx + p.r1[4] * ry + p.r1[5] + w * p.t1[1];
  const float bz = p.r1[6] * rx + p.r1[7] * ry + p.r1[8] + w * p.t1[2];
  if (!(az > kMinScaledZ && bz > kMinScaledZ)) {
    d[0] = d[1] = d[2] = d[3] = 0.0f;
    return;
  }
  const float ia = 1.0f / az, ib = 1.0f / bz;
  d[0] = p.fx * ax * ia + p.cx - x;
  d[1] = p.fy * ay * ia + p.cy - y;
  d[2] = p.fx * bx * ib + p.cx - x;
  d[3] = p.fy * by * ib + p.cy - y;
  for (int k = 0; k < 4; ++k) d[k] = std::min(std::max(d[k], -p.margin), p.margin);
}

inline float sample(const FlowBlur::Pass& p, float sx, float sy) {
  sx = std::min(std::max(sx, 0.0f), p.xmax);
  sy = std::min(std::max(sy, 0.0f), p.ymax);
  const int xi = static_cast<int>(sx), yi = static_cast<int>(sy);
  const float fx = sx - static_cast<float>(xi), fy = sy - static_cast<float>(yi);
  const float* q = p.radiance + yi * p.stride + xi;
  const float a = q[0] + fx * (q[1] - q[0]);
  const float b = q[p.stride] + fx * (q[p.stride + 1] - q[p.stride]);
  return a + fy * (b - a);
}

/// Each pixel's path: displacement at the start (dx, dy) and its change to the end (ex, ey).
struct Paths {
  alignas(32) float dx[kChunk], dy[kChunk], ex[kChunk], ey[kChunk];
  int samples[kChunk / kGroup];
};

/// Paths of pixels [0, n) of a group (n <= kGroup) one at a time; returns the group's sample count.
int paths_scalar(const FlowBlur::Pass& p, const float* xs, const float* ys, int n, float* dx, float* dy, float* ex,
                 float* ey) {
  float longest = 0.0f;
  for (int k = 0; k < n; ++k) {
    float d[4];
    displacement(p, xs[k], ys[k], d);
    dx[k] = d[0], dy[k] = d[1];
    ex[k] = d[2] - d[0], ey[k] = d[3] - d[1];
    longest = std::max(longest, std::ceil(std::sqrt(ex[k] * ex[k] + ey[k] * ey[k]) * p.inv_step));
  }
  return std::clamp(static_cast<int>(longest), 1, p.max_samples);
}

void samples_scalar(const FlowBlur::Pass& p, const float* xs, const float* ys, int n, const float* dx, const float* dy,
                    const float* ex, const float* ey, int samples, float* out) {
  const float inv_n = 1.0f / static_cast<float>(samples);
  const float scale = p.weight * inv_n;
  for (int k = 0; k < n; ++k) {
    float acc = 0.0f;
    for (int s = 0; s < samples; ++s) {
      const float f = (static_cast<float>(s) + 0.5f) * inv_n;
      acc += sample(p, xs[k] - (dx[k] + f * ex[k]), ys[k] - (dy[k] + f * ey[k]));
    }
    out[k] = p.add ? out[k] + scale * acc : scale * acc;
  }
}

#ifdef PLLVO_FLOW_BLUR_AVX2
struct Vec3x8 {
  __m256 x, y, z;
};

__attribute__((target("avx2"))) inline __m256 transform_row8(const float* r, float t, __m256 rx, __m256 ry, __m256 w) {
  const __m256 a = _mm256_add_ps(_mm256_mul_ps(_mm256_set1_ps(r[0]), rx), _mm256_mul_ps(_mm256_set1_ps(r[1]), ry));
  return _mm256_add_ps(_mm256_add_ps(a, _mm256_set1_ps(r[2])), _mm256_mul_ps(w, _mm256_set1_ps(t)));
}

__attribute__((target("avx2"))) inline Vec3x8 transform8(const float* r, const float* t, __m256 rx, __m256 ry,
                                                          __m256 w) {
  return {transform_row8(r, t[0], rx, ry, w), transform_row8(r + 3, t[1], rx, ry, w),
          transform_row8(r + 6, t[2], rx, ry, w)};
}

__attribute__((target("avx2"))) inline __m256 clamp8(__m256 v, __m256 lo, __m256 hi) {
  return _mm256_min_ps(_mm256_max_ps(v, lo), hi);
}

/// Image coordinate minus the pixel's, clamped to the margin; 0 in invalid lanes.
__attribute__((target("avx2"))) inline __m256 displacement8(__m256 f, __m256 v, __m256 inv, __m256 c, __m256 origin,
                                                             __m256 valid, __m256 lo, __m256 hi) {
  const __m256 d = _mm256_sub_ps(_mm256_add_ps(_mm256_mul_ps(_mm256_mul_ps(f, v), inv), c), origin);
  return clamp8(_mm256_and_ps(d, valid), lo, hi);
}

__attribute__((target("avx2"))) inline __m256 sample8(const FlowBlur::Pass& p, __m256 sx, __m256 sy) {
  const __m256 zero = _mm256_setzero_ps();
  sx = clamp8(sx, zero, _mm256_set1_ps(p.xmax));
  sy = clamp8(sy, zero, _mm256_set1_ps(p.ymax));
  const __m256i xi = _mm256_cvttps_epi32(sx), yi = _mm256_cvttps_epi32(sy);
  const __m256 fx = _mm256_sub_ps(sx, _mm256_cvtepi32_ps(xi)), fy = _mm256_sub_ps(sy, _mm256_cvtepi32_ps(yi));
  const __m256i idx = _mm256_add_epi32(_mm256_mullo_epi32(yi, _mm256_set1_epi32(p.stride)), xi);
  // Plain loads of each lane's 2 x 2 taps: faster than gathers here, whose cache misses
  // stall the whole instruction.
  alignas(32) int32_t at[8];
  alignas(32) float t00[8], t01[8], t10[8], t11[8];
  _mm256_store_si256(reinterpret_cast<__m256i*>(at), idx);
  for (int k = 0; k < 8; ++k) {
    const float* q = p.radiance + at[k];
    t00[k] = q[0], t01[k] = q[1], t10[k] = q[p.stride], t11[k] = q[p.stride + 1];
  }
  const __m256 p00 = _mm256_load_ps(t00), p01 = _mm256_load_ps(t01);
  const __m256 p10 = _mm256_load_ps(t10), p11 = _mm256_load_ps(t11);
  const __m256 a = _mm256_add_ps(p00, _mm256_mul_ps(fx, _mm256_sub_ps(p01, p00)));
  const __m256 b = _mm256_add_ps(p10, _mm256_mul_ps(fx, _mm256_sub_ps(p11, p10)));
  return _mm256_add_ps(a, _mm256_mul_ps(fy, _mm256_sub_ps(b, a)));
}

/// paths_scalar for eight pixels at once (the same operations).
__attribute__((target("avx2"))) int paths_avx2(const FlowBlur::Pass& p, const float* xs, const float* ys, float* dx,
                                               float* dy, float* ex, float* ey) {
  const __m256 x = _mm256_loadu_ps(xs), y = _mm256_loadu_ps(ys);
  const __m256 rx = _mm256_mul_ps(_mm256_sub_ps(x, _mm256_set1_ps(p.cx)), _mm256_set1_ps(p.ifx));
  const __m256 ry = _mm256_mul_ps(_mm256_sub_ps(y, _mm256_set1_ps(p.cy)), _mm256_set1_ps(p.ify));
  const __m256i didx = _mm256_add_epi32(_mm256_mullo_epi32(_mm256_cvtps_epi32(y), _mm256_set1_epi32(p.stride)),
                                        _mm256_cvtps_epi32(x));
  // Eight plain loads: faster than a gather here, whose misses stall the whole instruction.
  alignas(32) int32_t at[kGroup];
  alignas(32) float wv[kGroup];
  _mm256_store_si256(reinterpret_cast<__m256i*>(at), didx);
  for (int k = 0; k < kGroup; ++k) wv[k] = p.inv_depth[at[k]];
  const __m256 w = _mm256_load_ps(wv);
  const Vec3x8 A = transform8(p.r0, p.t0, rx, ry, w), B = transform8(p.r1, p.t1, rx, ry, w);
  const __m256 min_z = _mm256_set1_ps(kMinScaledZ), one = _mm256_set1_ps(1.0f);
  const __m256 valid = _mm256_and_ps(_mm256_cmp_ps(A.z, min_z, _CMP_GT_OQ), _mm256_cmp_ps(B.z, min_z, _CMP_GT_OQ));
  const __m256 ia = _mm256_div_ps(one, A.z), ib = _mm256_div_ps(one, B.z);
  const __m256 fx = _mm256_set1_ps(p.fx), fy = _mm256_set1_ps(p.fy), cx = _mm256_set1_ps(p.cx),
               cy = _mm256_set1_ps(p.cy);
  const __m256 lo = _mm256_set1_ps(-p.margin), hi = _mm256_set1_ps(p.margin);
  const __m256 dax = displacement8(fx, A.x, ia, cx, x, valid, lo, hi);
  const __m256 day = displacement8(fy, A.y, ia, cy, y, valid, lo, hi);
  const __m256 dbx = displacement8(fx, B.x, ib, cx, x, valid, lo, hi);
  const __m256 dby = displacement8(fy, B.y, ib, cy, y, valid, lo, hi);
  const __m256 vx = _mm256_sub_ps(dbx, dax), vy = _mm256_sub_ps(dby, day);
  _mm256_store_ps(dx, dax);
  _mm256_store_ps(dy, day);
  _mm256_store_ps(ex, vx);
  _mm256_store_ps(ey, vy);
  __m256 len = _mm256_ceil_ps(_mm256_mul_ps(_mm256_sqrt_ps(_mm256_add_ps(_mm256_mul_ps(vx, vx), _mm256_mul_ps(vy, vy))),
                                            _mm256_set1_ps(p.inv_step)));
  len = _mm256_max_ps(len, _mm256_permute2f128_ps(len, len, 1));
  len = _mm256_max_ps(len, _mm256_permute_ps(len, 0x4e));
  len = _mm256_max_ps(len, _mm256_permute_ps(len, 0xb1));
  return std::clamp(static_cast<int>(_mm256_cvtss_f32(len)), 1, p.max_samples);
}

/// samples_scalar for eight pixels at once (the same operations).
__attribute__((target("avx2"))) void samples_avx2(const FlowBlur::Pass& p, const float* xs, const float* ys,
                                                  const float* dx, const float* dy, const float* ex, const float* ey,
                                                  int samples, float* out) {
  const __m256 x = _mm256_loadu_ps(xs), y = _mm256_loadu_ps(ys);
  const __m256 dax = _mm256_load_ps(dx), day = _mm256_load_ps(dy);
  const __m256 vx = _mm256_load_ps(ex), vy = _mm256_load_ps(ey);
  const float inv_n = 1.0f / static_cast<float>(samples);
  const float scale = p.weight * inv_n;
  __m256 acc = _mm256_setzero_ps();
  for (int s = 0; s < samples; ++s) {
    const __m256 f = _mm256_set1_ps((static_cast<float>(s) + 0.5f) * inv_n);
    const __m256 sx = _mm256_sub_ps(x, _mm256_add_ps(dax, _mm256_mul_ps(f, vx)));
    const __m256 sy = _mm256_sub_ps(y, _mm256_add_ps(day, _mm256_mul_ps(f, vy)));
    acc = _mm256_add_ps(acc, sample8(p, sx, sy));
  }
  __m256 v = _mm256_mul_ps(_mm256_set1_ps(scale), acc);
  if (p.add) v = _mm256_add_ps(_mm256_loadu_ps(out), v);
  _mm256_storeu_ps(out, v);
}
#endif

}  // namespace

FlowBlur::FlowBlur(const LensModel& lens, double step_px, int max_samples, bool simd)
    : step_px_(static_cast<float>(step_px)), max_samples_(max_samples) {
  if (!(step_px > 0) || max_samples < 1) throw InternalError("FlowBlur: needs step_px > 0 and max_samples >= 1");
  const IdealView& view = lens.ideal_view();
  const cv::Mat& xy = lens.ideal_coordinates();
  width_ = xy.cols, height_ = xy.rows;
  ideal_width_ = view.width, ideal_height_ = view.height;
  fx_ = static_cast<float>(view.fx), fy_ = static_cast<float>(view.fy);
  cx_ = static_cast<float>(view.cx), cy_ = static_cast<float>(view.cy);
  const size_t n = static_cast<size_t>(width_) * height_;
  x_.resize(n), y_.resize(n);
  for (int v = 0; v < height_; ++v)
    for (int u = 0; u < width_; ++u) {
      const cv::Vec2f p = xy.at<cv::Vec2f>(v, u);
      x_[static_cast<size_t>(v) * width_ + u] = p[0];
      y_[static_cast<size_t>(v) * width_ + u] = p[1];
    }
#ifdef PLLVO_FLOW_BLUR_AVX2
  avx2_ = simd && __builtin_cpu_supports("avx2");
#else
  (void)simd;
#endif
}

double FlowBlur::accumulate(const Rasterizer& render, const Eigen::Isometry3d& T_start_render,
                            const Eigen::Isometry3d& T_end_render, float weight, const BlurRegion& region,
                            cv::Mat& image, bool add) const {
  const cv::Mat& rad = render.radiance();
  if (rad.cols != ideal_width_ || rad.rows != ideal_height_ || !rad.isContinuous() ||
      !render.inverse_depth().isContinuous())
    throw InternalError("FlowBlur: the render is not of the lens's ideal view");
  if (add && (image.type() != CV_32F || image.cols != width_ || image.rows != height_ || !image.isContinuous()))
    throw InternalError("FlowBlur: cannot add to an image of another size or type");
  if (!add) image.create(height_, width_, CV_32F);

  Pass p;
  p.radiance = rad.ptr<float>(0);
  p.inv_depth = render.inverse_depth().ptr<float>(0);
  p.stride = ideal_width_;
  p.xmax = static_cast<float>(ideal_width_ - 2);
  p.ymax = static_cast<float>(ideal_height_ - 2);
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      p.r0[3 * r + c] = static_cast<float>(T_start_render.linear()(r, c));
      p.r1[3 * r + c] = static_cast<float>(T_end_render.linear()(r, c));
    }
    p.t0[r] = static_cast<float>(T_start_render.translation()[r]);
    p.t1[r] = static_cast<float>(T_end_render.translation()[r]);
  }
  p.fx = fx_, p.fy = fy_, p.cx = cx_, p.cy = cy_;
  p.ifx = 1.0f / fx_, p.ify = 1.0f / fy_;
  // The bilinear taps of a sample reach one pixel further than the sample itself.
  p.margin = static_cast<float>(std::max(region.margin - 1, 0));
  p.inv_step = 1.0f / step_px_;
  p.max_samples = max_samples_;
  p.weight = weight;
  p.add = add;

  float* out = image.ptr<float>(0);
  const size_t n = x_.size();
  size_t samples = 0;
  // Paths for a chunk of pixels first, then their samples: the two loops have no dependency
  // chain between groups, so the CPU overlaps their memory accesses.
  Paths paths;
  // The reads of the render follow the lens's curves through it, which the hardware
  // prefetcher does not foresee: ask for the lines of pixels a few groups ahead.
  auto prefetch = [this](const Pass& pass, size_t i, size_t count) {
    if (i >= count) return;
    for (size_t j : {i, std::min(i + kGroup - 1, count - 1)}) {
      const int at = static_cast<int>(y_[j]) * pass.stride + static_cast<int>(x_[j]);
      __builtin_prefetch(pass.inv_depth + at);
      __builtin_prefetch(pass.radiance + at);
      __builtin_prefetch(pass.radiance + at + pass.stride);
    }
  };
  for (size_t c0 = 0; c0 < n; c0 += kChunk) {
    const int m = static_cast<int>(std::min<size_t>(kChunk, n - c0));
    const float *xs = &x_[c0], *ys = &y_[c0];
    for (int g = 0; g * kGroup < m; ++g) {
      const int k = g * kGroup, len = std::min(kGroup, m - k);
      prefetch(p, c0 + k + kPrefetchAhead, n);
#ifdef PLLVO_FLOW_BLUR_AVX2
      if (avx2_ && len == kGroup) {
        paths.samples[g] = paths_avx2(p, xs + k, ys + k, paths.dx + k, paths.dy + k, paths.ex + k, paths.ey + k);
        continue;
      }
#endif
      paths.samples[g] = paths_scalar(p, xs + k, ys + k, len, paths.dx + k, paths.dy + k, paths.ex + k, paths.ey + k);
    }
    for (int g = 0; g * kGroup < m; ++g) {
      const int k = g * kGroup, len = std::min(kGroup, m - k);
      samples += paths.samples[g];
#ifdef PLLVO_FLOW_BLUR_AVX2
      if (avx2_ && len == kGroup) {
        samples_avx2(p, xs + k, ys + k, paths.dx + k, paths.dy + k, paths.ex + k, paths.ey + k, paths.samples[g],
                     out + c0 + k);
        continue;
      }
#endif
      samples_scalar(p, xs + k, ys + k, len, paths.dx + k, paths.dy + k, paths.ex + k, paths.ey + k, paths.samples[g],
                     out + c0 + k);
    }
  }
  return static_cast<double>(samples) * kGroup / static_cast<double>(n);
}

}  // namespace pllvo::synth
