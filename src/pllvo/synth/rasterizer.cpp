#include "pllvo/synth/rasterizer.h"

#include <algorithm>
#include <cmath>
#include <climits>
#include <cstdint>
#include <cstring>

#include <Eigen/LU>

#include "pllvo/common/error.h"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define PLLVO_SYNTH_AVX2 1
#endif

namespace pllvo::synth {

// Shading runs on 8 pixels at a time with AVX2 when the CPU has it, else one pixel at a time.
// Both paths perform the same single-precision operations in the same order (no FMA), so
// they produce identical images.
struct Rasterizer::QuadShading {
  // Homography rows in level-0 texel units: S*w = a00 x + a01 y + a02, T*w = ..., w = 1/z.
  float a00, a01, a10, a11, a20, a21;
  const uint16_t* data;
  int num_levels;
  float max_lod;
  float scale;
  // Per mip level: level texels per level-0 texel, last valid coordinate, layout.
  float sx[32], sy[32], xmax[32], ymax[32];
  int step[32], offset[32];
  int index;
};

namespace {

/// log2 accurate to ~0.01, plenty to pick a mip level (identical in the SIMD path).
inline float fast_log2(float v) {
  uint32_t bits;
  std::memcpy(&bits, &v, sizeof bits);
  const float e = static_cast<float>(static_cast<int>((bits >> 23) & 255) - 127);
  const float m = static_cast<float>(static_cast<int>(bits & 0x7fffff)) * (1.0f / 8388608.0f);
  return e + m * (1.3465f - 0.3465f * m);
}

/// Bilinear lookup in level l at level-0 texel coordinates (S, T); the coordinate is
/// clamped to the level, so edges repeat (clamp-to-edge).
inline float bilinear(const Rasterizer::QuadShading& q, int l, float S, float T) {
  float x = S * q.sx[l] - 0.5f, y = T * q.sy[l] - 0.5f;
  x = std::min(std::max(x, 0.0f), q.xmax[l]);
  y = std::min(std::max(y, 0.0f), q.ymax[l]);
  const int xi = static_cast<int>(x), yi = static_cast<int>(y);
  const float fx = x - static_cast<float>(xi), fy = y - static_cast<float>(yi);
  const uint16_t* p = q.data + q.offset[l] + yi * q.step[l] + xi;
  const float p00 = p[0], p01 = p[1], p10 = p[q.step[l]], p11 = p[q.step[l] + 1];
  const float a = p00 + fx * (p01 - p00);
  const float b = p10 + fx * (p11 - p10);
  return a + fy * (b - a);
}

/// Texture value of one pixel (S, T: level-0 texel coordinates; iw = 1/w).
inline float shade_pixel(const Rasterizer::QuadShading& q, float S, float T, float iw) {
  const float dsdx = (q.a00 - S * q.a20) * iw, dtdx = (q.a10 - T * q.a20) * iw;
  const float dsdy = (q.a01 - S * q.a21) * iw, dtdy = (q.a11 - T * q.a21) * iw;
  const float rho2 = std::max(dsdx * dsdx + dtdx * dtdx, dsdy * dsdy + dtdy * dtdy);
  float lod = rho2 <= 1.0f ? 0.0f : std::min(0.5f * fast_log2(rho2), q.max_lod);
  const int l = static_cast<int>(lod);
  const float f = lod - static_cast<float>(l);
  const float v = bilinear(q, l, S, T);
  if (f == 0.0f) return v;
  return v + f * (bilinear(q, std::min(l + 1, q.num_levels - 1), S, T) - v);
}

struct Span {
  float* rad;
  float* zb;
  int32_t* id;
  int c0, c1;
  int row_end;       // columns of the row buffers (whole-vector stores stay below it)
  float w0, s0, t0;  // w, S*w and T*w at column c0
};

void shade_span_scalar(const Rasterizer::QuadShading& q, const Span& sp, float gain) {
  const float scale = q.scale * gain;
  for (int c = sp.c0; c < sp.c1; ++c) {
    const float j = static_cast<float>(c - sp.c0);
    const float w = sp.w0 + j * q.a20;
    if (!(w > sp.zb[c])) continue;
    const float iw = 1.0f / w;
    const float S = (sp.s0 + j * q.a00) * iw, T = (sp.t0 + j * q.a10) * iw;
    sp.rad[c] = shade_pixel(q, S, T, iw) * scale;
    sp.zb[c] = w;
    if (sp.id) sp.id[c] = q.index;
  }
}

#ifdef PLLVO_SYNTH_AVX2
__attribute__((target("avx2"))) inline __m256 bilinear8(const Rasterizer::QuadShading& q, int l, __m256 S,
                                                          __m256 T) {
  const __m256 half = _mm256_set1_ps(0.5f), zero = _mm256_setzero_ps();
  __m256 x = _mm256_sub_ps(_mm256_mul_ps(S, _mm256_set1_ps(q.sx[l])), half);
  __m256 y = _mm256_sub_ps(_mm256_mul_ps(T, _mm256_set1_ps(q.sy[l])), half);
  x = _mm256_min_ps(_mm256_max_ps(x, zero), _mm256_set1_ps(q.xmax[l]));
  y = _mm256_min_ps(_mm256_max_ps(y, zero), _mm256_set1_ps(q.ymax[l]));
  const __m256i xi = _mm256_cvttps_epi32(x), yi = _mm256_cvttps_epi32(y);
  const __m256 fx = _mm256_sub_ps(x, _mm256_cvtepi32_ps(xi)), fy = _mm256_sub_ps(y, _mm256_cvtepi32_ps(yi));
  const __m256i step = _mm256_set1_epi32(q.step[l]);
  const __m256i idx =
      _mm256_add_epi32(_mm256_add_epi32(_mm256_set1_epi32(q.offset[l]), _mm256_mullo_epi32(yi, step)), xi);
  // One 32-bit load fetches two horizontally adjacent 16-bit texels; plain loads, because a
  // gather stalls as a whole on any cache miss.
  alignas(32) int32_t at[8];
  alignas(32) uint32_t top[8], bottom[8];
  _mm256_store_si256(reinterpret_cast<__m256i*>(at), idx);
  for (int k = 0; k < 8; ++k) {
    std::memcpy(&top[k], q.data + at[k], sizeof(uint32_t));
    std::memcpy(&bottom[k], q.data + at[k] + q.step[l], sizeof(uint32_t));
  }
  const __m256i g0 = _mm256_load_si256(reinterpret_cast<const __m256i*>(top));
  const __m256i g1 = _mm256_load_si256(reinterpret_cast<const __m256i*>(bottom));
  const __m256i lo = _mm256_set1_epi32(0xffff);
  const __m256 p00 = _mm256_cvtepi32_ps(_mm256_and_si256(g0, lo)), p01 = _mm256_cvtepi32_ps(_mm256_srli_epi32(g0, 16));
  const __m256 p10 = _mm256_cvtepi32_ps(_mm256_and_si256(g1, lo)), p11 = _mm256_cvtepi32_ps(_mm256_srli_epi32(g1, 16));
  const __m256 a = _mm256_add_ps(p00, _mm256_mul_ps(fx, _mm256_sub_ps(p01, p00)));
  const __m256 b = _mm256_add_ps(p10, _mm256_mul_ps(fx, _mm256_sub_ps(p11, p10)));
  return _mm256_add_ps(a, _mm256_mul_ps(fy, _mm256_sub_ps(b, a)));
}

__attribute__((target("avx2"))) inline __m256 fast_log2_8(__m256 v) {
  const __m256i bits = _mm256_castps_si256(v);
  const __m256 e = _mm256_cvtepi32_ps(
      _mm256_sub_epi32(_mm256_and_si256(_mm256_srli_epi32(bits, 23), _mm256_set1_epi32(255)), _mm256_set1_epi32(127)));
  const __m256 m = _mm256_mul_ps(_mm256_cvtepi32_ps(_mm256_and_si256(bits, _mm256_set1_epi32(0x7fffff))),
                                 _mm256_set1_ps(1.0f / 8388608.0f));
  return _mm256_add_ps(e, _mm256_mul_ps(m, _mm256_sub_ps(_mm256_set1_ps(1.3465f), _mm256_mul_ps(_mm256_set1_ps(0.3465f), m))));
}

__attribute__((target("avx2"))) inline __m256i hmin8(__m256i v) {
  v = _mm256_min_epi32(v, _mm256_permute2x128_si256(v, v, 1));
  v = _mm256_min_epi32(v, _mm256_shuffle_epi32(v, 0x4e));
  return _mm256_min_epi32(v, _mm256_shuffle_epi32(v, 0xb1));
}

__attribute__((target("avx2"))) inline __m256i hmax8(__m256i v) {
  v = _mm256_max_epi32(v, _mm256_permute2x128_si256(v, v, 1));
  v = _mm256_max_epi32(v, _mm256_shuffle_epi32(v, 0x4e));
  return _mm256_max_epi32(v, _mm256_shuffle_epi32(v, 0xb1));
}

__attribute__((target("avx2"))) void shade_span_avx2(const Rasterizer::QuadShading& q, const Span& sp, float gain) {
  const float scale = q.scale * gain;
  const __m256 lane = _mm256_setr_ps(0, 1, 2, 3, 4, 5, 6, 7);
  const __m256 one = _mm256_set1_ps(1.0f);
  for (int c = sp.c0; c < sp.c1; c += 8) {
    const int n = std::min(8, sp.c1 - c);
    const __m256i valid = _mm256_cmpgt_epi32(_mm256_set1_epi32(n), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
    const __m256 j = _mm256_add_ps(_mm256_set1_ps(static_cast<float>(c - sp.c0)), lane);
    const __m256 w = _mm256_add_ps(_mm256_set1_ps(sp.w0), _mm256_mul_ps(j, _mm256_set1_ps(q.a20)));
    const __m256 z = n == 8 ? _mm256_loadu_ps(sp.zb + c) : _mm256_maskload_ps(sp.zb + c, valid);
    const __m256i pass = _mm256_and_si256(valid, _mm256_castps_si256(_mm256_cmp_ps(w, z, _CMP_GT_OQ)));
    if (_mm256_testz_si256(pass, pass)) continue;
    const __m256 iw = _mm256_div_ps(one, w);
    const __m256 S = _mm256_mul_ps(_mm256_add_ps(_mm256_set1_ps(sp.s0), _mm256_mul_ps(j, _mm256_set1_ps(q.a00))), iw);
    const __m256 T = _mm256_mul_ps(_mm256_add_ps(_mm256_set1_ps(sp.t0), _mm256_mul_ps(j, _mm256_set1_ps(q.a10))), iw);
    const __m256 a20 = _mm256_set1_ps(q.a20), a21 = _mm256_set1_ps(q.a21);
    const __m256 dsdx = _mm256_mul_ps(_mm256_sub_ps(_mm256_set1_ps(q.a00), _mm256_mul_ps(S, a20)), iw);
    const __m256 dtdx = _mm256_mul_ps(_mm256_sub_ps(_mm256_set1_ps(q.a10), _mm256_mul_ps(T, a20)), iw);
    const __m256 dsdy = _mm256_mul_ps(_mm256_sub_ps(_mm256_set1_ps(q.a01), _mm256_mul_ps(S, a21)), iw);
    const __m256 dtdy = _mm256_mul_ps(_mm256_sub_ps(_mm256_set1_ps(q.a11), _mm256_mul_ps(T, a21)), iw);
    const __m256 rho2 = _mm256_max_ps(_mm256_add_ps(_mm256_mul_ps(dsdx, dsdx), _mm256_mul_ps(dtdx, dtdx)),
                                      _mm256_add_ps(_mm256_mul_ps(dsdy, dsdy), _mm256_mul_ps(dtdy, dtdy)));
    const __m256 lod_raw = _mm256_min_ps(_mm256_mul_ps(_mm256_set1_ps(0.5f), fast_log2_8(rho2)), _mm256_set1_ps(q.max_lod));
    const __m256 lod = _mm256_blendv_ps(lod_raw, _mm256_setzero_ps(), _mm256_cmp_ps(rho2, one, _CMP_LE_OQ));
    const __m256i li = _mm256_cvttps_epi32(lod);
    const __m256 f = _mm256_sub_ps(lod, _mm256_cvtepi32_ps(li));
    // One mip level for the passing lanes (the usual case) takes the vector path.
    const __m256i lmin = hmin8(_mm256_blendv_epi8(_mm256_set1_epi32(INT32_MAX), li, pass));
    const __m256i lmax = hmax8(_mm256_blendv_epi8(_mm256_set1_epi32(INT32_MIN), li, pass));
    const int l = _mm256_cvtsi256_si32(lmin);
    if (l != _mm256_cvtsi256_si32(lmax)) {  // the mip level changes inside these 8 pixels: one at a time
      alignas(32) int passed[8];
      alignas(32) float Sv[8], Tv[8], iwv[8], wv[8];
      _mm256_store_si256(reinterpret_cast<__m256i*>(passed), pass);
      _mm256_store_ps(Sv, S);
      _mm256_store_ps(Tv, T);
      _mm256_store_ps(iwv, iw);
      _mm256_store_ps(wv, w);
      for (int k = 0; k < n; ++k) {
        if (!passed[k]) continue;
        sp.rad[c + k] = shade_pixel(q, Sv[k], Tv[k], iwv[k]) * scale;
        sp.zb[c + k] = wv[k];
        if (sp.id) sp.id[c + k] = q.index;
      }
      continue;
    }
    __m256 v = bilinear8(q, l, S, T);
    const int l1 = std::min(l + 1, q.num_levels - 1);
    if (_mm256_movemask_ps(_mm256_cmp_ps(f, _mm256_setzero_ps(), _CMP_NEQ_OQ)) != 0) v = _mm256_add_ps(v, _mm256_mul_ps(f, _mm256_sub_ps(bilinear8(q, l1, S, T), v)));
    v = _mm256_mul_ps(v, _mm256_set1_ps(scale));
    if (c + 8 <= sp.row_end) {  // masked stores are slow on some CPUs: blend with what is there
      const __m256 m = _mm256_castsi256_ps(pass);
      _mm256_storeu_ps(sp.rad + c, _mm256_blendv_ps(_mm256_loadu_ps(sp.rad + c), v, m));
      _mm256_storeu_ps(sp.zb + c, _mm256_blendv_ps(_mm256_loadu_ps(sp.zb + c), w, m));
      if (sp.id)
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(sp.id + c),
                            _mm256_blendv_epi8(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(sp.id + c)),
                                               _mm256_set1_epi32(q.index), pass));
    } else {
      _mm256_maskstore_ps(sp.rad + c, pass, v);
      _mm256_maskstore_ps(sp.zb + c, pass, w);
      if (sp.id) _mm256_maskstore_epi32(sp.id + c, pass, _mm256_set1_epi32(q.index));
    }
  }
}
#endif

}  // namespace

Rasterizer::Rasterizer(IdealView view, double near_m, bool simd, int supersample)
    : view_(std::move(view)), near_(near_m), factor_(supersample) {
  if (view_.width <= 0 || view_.height <= 0 || static_cast<int>(view_.drawn.first.size()) != view_.height + 1)
    throw InternalError("Rasterizer: malformed ideal view");
  if (factor_ < 1 || factor_ > 4) throw InternalError("Rasterizer: supersample must be in [1, 4]");
  // Zero outside the drawn region once; render() clears only the drawn region.
  radiance_ = cv::Mat::zeros(view_.height, view_.width, CV_32F);
  inv_depth_ = cv::Mat::zeros(view_.height, view_.width, CV_32F);
  ids_ = cv::Mat(view_.height, view_.width, CV_32S, cv::Scalar(-1));
  sample_view_ = view_;
  if (factor_ == 1) {
    sample_radiance_ = radiance_, sample_inv_depth_ = inv_depth_, sample_ids_ = ids_;
  } else {
    // Sample (i, j) of pixel (x, y) sits at x + (i + 0.5) / f - 0.5: the f x f grid centred on it.
    const double f = factor_;
    sample_view_.width *= factor_, sample_view_.height *= factor_;
    sample_view_.fx *= f, sample_view_.fy *= f;
    sample_view_.cx = f * view_.cx + (f - 1) / 2, sample_view_.cy = f * view_.cy + (f - 1) / 2;
    sample_view_.drawn = sample_runs(view_.drawn);
    sample_radiance_ = cv::Mat::zeros(sample_view_.height, sample_view_.width, CV_32F);
    sample_inv_depth_ = cv::Mat::zeros(sample_view_.height, sample_view_.width, CV_32F);
    sample_ids_ = cv::Mat(sample_view_.height, sample_view_.width, CV_32S, cv::Scalar(-1));
  }
#ifdef PLLVO_SYNTH_AVX2
  avx2_ = simd && __builtin_cpu_supports("avx2");
#else
  (void)simd;
#endif
}

RowRuns Rasterizer::sample_runs(const RowRuns& runs) const {
  RowRuns r;
  r.first.reserve(runs.first.size() * factor_);
  for (size_t y = 0; y + 1 < runs.first.size(); ++y)
    for (int i = 0; i < factor_; ++i) {
      r.first.push_back(static_cast<int>(r.begin.size()));
      for (int k = runs.first[y]; k < runs.first[y + 1]; ++k) {
        r.begin.push_back(runs.begin[k] * factor_);
        r.end.push_back(runs.end[k] * factor_);
      }
    }
  r.first.push_back(static_cast<int>(r.begin.size()));
  return r;
}

void Rasterizer::resolve(const RowRuns& runs) {
  const int f = factor_;
  const float inv_n = 1.0f / static_cast<float>(f * f);
  for (int y = 0; y < view_.height; ++y)
    for (int k = runs.first[y]; k < runs.first[y + 1]; ++k)
      for (int x = runs.begin[k]; x < runs.end[k]; ++x) {
        float sum = 0, nearest = 0;
        int32_t id = -1;
        for (int i = 0; i < f; ++i) {
          const float* rad = sample_radiance_.ptr<float>(y * f + i) + x * f;
          const float* zb = sample_inv_depth_.ptr<float>(y * f + i) + x * f;
          const int32_t* ids = with_ids_ ? sample_ids_.ptr<int32_t>(y * f + i) + x * f : nullptr;
          for (int j = 0; j < f; ++j) {
            sum += rad[j];
            if (zb[j] > nearest) nearest = zb[j], id = ids ? ids[j] : -1;
          }
        }
        radiance_.at<float>(y, x) = sum * inv_n;
        inv_depth_.at<float>(y, x) = nearest;
        if (with_ids_) ids_.at<int32_t>(y, x) = id;
      }
}

RowRuns RowRuns::from_mask(const cv::Mat& mask) {
  RowRuns r;
  r.first.reserve(mask.rows + 1);
  for (int y = 0; y < mask.rows; ++y) {
    r.first.push_back(static_cast<int>(r.begin.size()));
    const auto* m = mask.ptr<uint8_t>(y);
    for (int x = 0; x < mask.cols;) {
      if (!m[x]) {
        ++x;
        continue;
      }
      const int x0 = x;
      while (x < mask.cols && m[x]) ++x;
      r.begin.push_back(x0);
      r.end.push_back(x);
    }
  }
  r.first.push_back(static_cast<int>(r.begin.size()));
  return r;
}

size_t RowRuns::pixels() const {
  size_t n = 0;
  for (size_t k = 0; k < begin.size(); ++k) n += end[k] - begin[k];
  return n;
}

void Rasterizer::render(const Scene& scene, const RadianceState& radiance, const Eigen::Isometry3d& T_cam_world,
                        float gain, bool with_ids, const RowRuns* pixels) {
  with_ids_ = with_ids;
  const RowRuns& runs = pixels ? *pixels : view_.drawn;
  if (static_cast<int>(runs.first.size()) != view_.height + 1) throw InternalError("Rasterizer: runs of another view");
  RowRuns scaled;
  if (factor_ > 1 && pixels) scaled = sample_runs(runs);
  const RowRuns& samples = factor_ == 1 ? runs : pixels ? scaled : sample_view_.drawn;
  // Clear only what is drawn: most of the cost here is memory traffic.
  for (int y = 0; y < sample_view_.height; ++y)
    for (int k = samples.first[y]; k < samples.first[y + 1]; ++k) {
      std::fill_n(sample_radiance_.ptr<float>(y) + samples.begin[k], samples.end[k] - samples.begin[k], 0.0f);
      std::fill_n(sample_inv_depth_.ptr<float>(y) + samples.begin[k], samples.end[k] - samples.begin[k], 0.0f);
    }
  if (with_ids) {
    sample_ids_.setTo(-1);
    if (factor_ > 1) ids_.setTo(-1);
  }
  // Front to back, so that hidden pixels fail the depth test before their texture lookup.
  const Eigen::Vector3d eye = T_cam_world.inverse().translation();
  order_.clear();
  for (size_t i = 0; i < scene.quads.size(); ++i)
    if (scene.quads[i].faces(eye)) order_.emplace_back(distance_to_quad(scene.quads[i], eye), static_cast<int>(i));
  std::sort(order_.begin(), order_.end());
  for (const auto& [dist, i] : order_) draw_quad(scene.quads[i], i, radiance.quads[i], T_cam_world, gain, samples);
  if (factor_ > 1) resolve(runs);
}

void Rasterizer::draw_quad(const Quad& quad, int index, const MipTexture& tex, const Eigen::Isometry3d& T_cam_world,
                           float gain, const RowRuns& pixels) {
  Eigen::Vector3d P[4];
  for (int k = 0; k < 4; ++k) P[k] = T_cam_world * quad.corner(k);

  // Clip at the near plane (Sutherland-Hodgman against z >= near).
  Eigen::Vector3d poly[8];
  int n = 0;
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector3d& a = P[k];
    const Eigen::Vector3d& b = P[(k + 1) % 4];
    const bool ina = a.z() >= near_, inb = b.z() >= near_;
    if (ina) poly[n++] = a;
    if (ina != inb) poly[n++] = a + (near_ - a.z()) / (b.z() - a.z()) * (b - a);
  }
  if (n < 3) return;

  double xs[8], ys[8];
  double xmin = 1e300, xmax = -1e300, ymin = 1e300, ymax = -1e300;
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector2d p = sample_view_.project(poly[k]);
    xs[k] = p.x(), ys[k] = p.y();
    xmin = std::min(xmin, xs[k]), xmax = std::max(xmax, xs[k]);
    ymin = std::min(ymin, ys[k]), ymax = std::max(ymax, ys[k]);
  }
  if (xmax < 0 || ymax < 0 || xmin > sample_view_.width - 1 || ymin > sample_view_.height - 1) return;

  // [S, T, 1] / z = A * [x, y, 1] for ideal pixel (x, y): the plane's homography, with S and
  // T in level-0 texels.
  Eigen::Matrix3d M;
  M.col(0) = T_cam_world.linear() * quad.u;
  M.col(1) = T_cam_world.linear() * quad.v;
  M.col(2) = P[0];
  if (std::abs(M.determinant()) < 1e-9 * quad.area() * P[0].norm()) return;  // seen edge-on
  const IdealView& v = sample_view_;
  Eigen::Matrix3d Kinv;
  Kinv << 1 / v.fx, 0, -v.cx / v.fx, 0, 1 / v.fy, -v.cy / v.fy, 0, 0, 1;
  Eigen::Matrix3d A = M.inverse() * Kinv;
  const MipLevel& base = tex.levels.at(0);
  A.row(0) *= base.cols;
  A.row(1) *= base.rows;

  QuadShading q;
  q.a00 = static_cast<float>(A(0, 0)), q.a01 = static_cast<float>(A(0, 1));
  q.a10 = static_cast<float>(A(1, 0)), q.a11 = static_cast<float>(A(1, 1));
  q.a20 = static_cast<float>(A(2, 0)), q.a21 = static_cast<float>(A(2, 1));
  q.data = tex.data.data();
  q.num_levels = std::min<int>(32, static_cast<int>(tex.levels.size()));
  q.max_lod = static_cast<float>(q.num_levels - 1);
  q.scale = tex.scale;
  q.index = index;
  for (int l = 0; l < q.num_levels; ++l) {
    const MipLevel& d = tex.levels[l];
    q.sx[l] = static_cast<float>(static_cast<double>(d.cols) / base.cols);
    q.sy[l] = static_cast<float>(static_cast<double>(d.rows) / base.rows);
    q.xmax[l] = static_cast<float>(d.cols - 1);
    q.ymax[l] = static_cast<float>(d.rows - 1);
    q.step[l] = d.step;
    q.offset[l] = static_cast<int>(d.offset);
  }

  const int y0 = std::max(0, static_cast<int>(std::ceil(ymin)));
  const int y1 = std::min(sample_view_.height - 1, static_cast<int>(std::floor(ymax)));
  for (int y = y0; y <= y1; ++y) {
    // Span of pixel centres inside the convex polygon on this row.
    double xl = 1e300, xr = -1e300;
    for (int k = 0; k < n; ++k) {
      const int j = (k + 1) % n;
      const double ya = ys[k], yb = ys[j];
      if ((ya <= y && y < yb) || (yb <= y && y < ya)) {
        const double x = xs[k] + (y - ya) * (xs[j] - xs[k]) / (yb - ya);
        xl = std::min(xl, x), xr = std::max(xr, x);
      }
    }
    if (xl > xr) continue;
    const int x_begin = static_cast<int>(std::ceil(std::max(xl, -1.0)));
    const int x_end = static_cast<int>(std::ceil(std::min(xr, 1e9)));
    for (int k = pixels.first[y]; k < pixels.first[y + 1]; ++k) {
      Span sp;
      sp.c0 = std::max(x_begin, pixels.begin[k]);
      sp.c1 = std::min(x_end, pixels.end[k]);
      if (sp.c0 >= sp.c1) continue;
      sp.s0 = static_cast<float>(A(0, 0) * sp.c0 + A(0, 1) * y + A(0, 2));
      sp.t0 = static_cast<float>(A(1, 0) * sp.c0 + A(1, 1) * y + A(1, 2));
      sp.w0 = static_cast<float>(A(2, 0) * sp.c0 + A(2, 1) * y + A(2, 2));
      sp.row_end = sample_view_.width;
      sp.rad = sample_radiance_.ptr<float>(y);
      sp.zb = sample_inv_depth_.ptr<float>(y);
      sp.id = with_ids_ ? sample_ids_.ptr<int32_t>(y) : nullptr;
#ifdef PLLVO_SYNTH_AVX2
      if (avx2_) {
        shade_span_avx2(q, sp, gain);
        continue;
      }
#endif
      shade_span_scalar(q, sp, gain);
    }
  }
}

}  // namespace pllvo::synth
