#include "pllvo/synth/sensor.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "pllvo/common/error.h"
#include "pllvo/synth/random.h"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define PLLVO_SENSOR_AVX2 1
#endif

namespace pllvo::synth {

namespace {

constexpr int kNormalBits = 12;  // segments of the inverse normal CDF: 2^12
constexpr int kNormalSegments = 1 << kNormalBits;

/// Inverse normal CDF at the segment ends j / 4096 (j = 1..4095), found by bisection on
/// erfc; the two end values make each tail segment's mean equal the tail's conditional mean.
const std::array<float, kNormalSegments + 1>& inverse_normal_table() {
  static const std::array<float, kNormalSegments + 1> table = [] {
    std::array<float, kNormalSegments + 1> t{};
    auto quantile = [](double p) {
      double lo = -10, hi = 10;
      for (int i = 0; i < 100; ++i) {
        const double mid = 0.5 * (lo + hi);
        (0.5 * std::erfc(-mid / std::sqrt(2.0)) < p ? lo : hi) = mid;
      }
      return 0.5 * (lo + hi);
    };
    for (int j = 1; j < kNormalSegments; ++j) t[j] = static_cast<float>(quantile(static_cast<double>(j) / kNormalSegments));
    // E[Z | Z < z1] = -phi(z1) / Phi(z1); linear over the segment: (t0 + t1) / 2 equals it.
    const double z1 = t[1];
    const double tail_mean = -std::exp(-0.5 * z1 * z1) / std::sqrt(2 * M_PI) / (1.0 / kNormalSegments);
    t[0] = static_cast<float>(2 * tail_mean - z1);
    t[kNormalSegments] = -t[0];
    return t;
  }();
  return table;
}

/// A 32-bit integer hash (Wellons' lowbias32): a bijection with good avalanche.
inline uint32_t hash32(uint32_t x) {
  x ^= x >> 16;
  x *= 0x7feb352dU;
  x ^= x >> 15;
  x *= 0x846ca68bU;
  x ^= x >> 16;
  return x;
}

struct RecordPass {
  const float* radiance;
  const float* vignetting;
  const float* normal;  // inverse CDF table
  float to_electrons, full_well, read2, to_dn;
  uint32_t key0, key1;
  bool noise;
};

/// Standard normal deviate of pixel i: two keyed hash rounds, then the inverse CDF.
inline float normal_deviate(const RecordPass& p, uint32_t i) {
  const uint32_t h = hash32(hash32(i ^ p.key0) ^ p.key1);
  const uint32_t j = h >> (32 - kNormalBits);
  const float f = static_cast<float>(h & ((1U << (32 - kNormalBits)) - 1)) * (1.0f / (1U << (32 - kNormalBits)));
  return p.normal[j] + f * (p.normal[j + 1] - p.normal[j]);
}

void record_scalar(const RecordPass& p, size_t begin, size_t end, uint8_t* out) {
  for (size_t i = begin; i < end; ++i) {
    float e = std::min(p.radiance[i] * p.vignetting[i] * p.to_electrons, p.full_well);
    if (p.noise) e = e + std::sqrt(e + p.read2) * normal_deviate(p, static_cast<uint32_t>(i));
    const float dn = std::nearbyint(e * p.to_dn);
    out[i] = static_cast<uint8_t>(std::min(std::max(dn, 0.0f), 255.0f));
  }
}

#ifdef PLLVO_SENSOR_AVX2
__attribute__((target("avx2"))) inline __m256i hash32_8(__m256i x) {
  x = _mm256_xor_si256(x, _mm256_srli_epi32(x, 16));
  x = _mm256_mullo_epi32(x, _mm256_set1_epi32(0x7feb352d));
  x = _mm256_xor_si256(x, _mm256_srli_epi32(x, 15));
  x = _mm256_mullo_epi32(x, _mm256_set1_epi32(static_cast<int>(0x846ca68bU)));
  return _mm256_xor_si256(x, _mm256_srli_epi32(x, 16));
}

/// record_scalar on 8 pixels at a time (the same operations; end - begin a multiple of 8).
__attribute__((target("avx2"))) void record_avx2(const RecordPass& p, size_t begin, size_t end, uint8_t* out) {
  const __m256 k = _mm256_set1_ps(p.to_electrons), well = _mm256_set1_ps(p.full_well);
  const __m256 read2 = _mm256_set1_ps(p.read2), to_dn = _mm256_set1_ps(p.to_dn);
  const __m256i key0 = _mm256_set1_epi32(static_cast<int>(p.key0)), key1 = _mm256_set1_epi32(static_cast<int>(p.key1));
  const __m256i frac_mask = _mm256_set1_epi32((1 << (32 - kNormalBits)) - 1);
  const __m256 frac_scale = _mm256_set1_ps(1.0f / (1U << (32 - kNormalBits)));
  const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  for (size_t i = begin; i < end; i += 8) {
    __m256 e = _mm256_min_ps(_mm256_mul_ps(_mm256_mul_ps(_mm256_loadu_ps(p.radiance + i), _mm256_loadu_ps(p.vignetting + i)), k),
                             well);
    if (p.noise) {
      const __m256i idx = _mm256_add_epi32(_mm256_set1_epi32(static_cast<int>(i)), lane);
      const __m256i h = hash32_8(_mm256_xor_si256(hash32_8(_mm256_xor_si256(idx, key0)), key1));
      const __m256i j = _mm256_srli_epi32(h, 32 - kNormalBits);
      const __m256 f = _mm256_mul_ps(_mm256_cvtepi32_ps(_mm256_and_si256(h, frac_mask)), frac_scale);
      const __m256 t0 = _mm256_i32gather_ps(p.normal, j, 4);
      const __m256 t1 = _mm256_i32gather_ps(p.normal + 1, j, 4);
      const __m256 z = _mm256_add_ps(t0, _mm256_mul_ps(f, _mm256_sub_ps(t1, t0)));
      e = _mm256_add_ps(e, _mm256_mul_ps(_mm256_sqrt_ps(_mm256_add_ps(e, read2)), z));
    }
    // Round to nearest (even), saturate to [0, 255] while packing.
    const __m256i dn = _mm256_cvtps_epi32(_mm256_mul_ps(e, to_dn));
    const __m128i w16 = _mm_packs_epi32(_mm256_castsi256_si128(dn), _mm256_extracti128_si256(dn, 1));
    _mm_storel_epi64(reinterpret_cast<__m128i*>(out + i), _mm_packus_epi16(w16, w16));
  }
}
#endif

}  // namespace

SensorModel::SensorModel(const SensorSpec& spec, const cv::Mat& bearings) : spec_(spec) {
  vignetting_.create(bearings.size(), CV_32F);
  for (int r = 0; r < bearings.rows; ++r) {
    const auto* b = bearings.ptr<cv::Vec3f>(r);
    auto* v = vignetting_.ptr<float>(r);
    for (int c = 0; c < bearings.cols; ++c) {
      const float cos2 = b[c][2] * b[c][2];  // cos^2 of the field angle (unit bearings)
      v[c] = static_cast<float>(1.0 - spec.vignetting * (1.0 - cos2 * cos2));
    }
  }
#ifdef PLLVO_SENSOR_AVX2
  avx2_ = __builtin_cpu_supports("avx2");
#endif
}

void SensorModel::blur(cv::Mat& radiance) const {
  if (spec_.psf_sigma_px > 0) cv::GaussianBlur(radiance, radiance, cv::Size(), spec_.psf_sigma_px);
}

void SensorModel::electrons(const cv::Mat& radiance, double light, double exposure_ms, cv::Mat& out) const {
  cv::multiply(radiance, vignetting_, out, light * exposure_ms * spec_.sensitivity);
  cv::min(out, spec_.full_well_e, out);
}

cv::Mat SensorModel::expected_dn(const cv::Mat& electrons, double gain) const {
  cv::Mat dn = electrons * (gain / spec_.electrons_per_dn);
  cv::min(dn, 255.0, dn);
  return dn;
}

cv::Mat SensorModel::record(const cv::Mat& radiance, double light, double exposure_ms, double gain,
                            uint64_t noise_seed, bool noise) const {
  if (radiance.type() != CV_32F || radiance.size() != vignetting_.size() || !radiance.isContinuous())
    throw InternalError("SensorModel::record: expected continuous CV_32F radiance of the camera's size");
  cv::Mat image(radiance.size(), CV_8U);
  RecordPass p;
  p.radiance = radiance.ptr<float>(0);
  p.vignetting = vignetting_.ptr<float>(0);
  p.normal = inverse_normal_table().data();
  p.to_electrons = static_cast<float>(light * exposure_ms * spec_.sensitivity);
  p.full_well = static_cast<float>(spec_.full_well_e);
  p.read2 = static_cast<float>(spec_.read_noise_e * spec_.read_noise_e);
  p.to_dn = static_cast<float>(gain / spec_.electrons_per_dn);
  const uint64_t key = mix64(noise_seed);
  p.key0 = static_cast<uint32_t>(key), p.key1 = static_cast<uint32_t>(key >> 32);
  p.noise = noise;
  const size_t n = radiance.total();
  size_t done = 0;
#ifdef PLLVO_SENSOR_AVX2
  if (avx2_) {
    done = n - n % 8;
    record_avx2(p, 0, done, image.ptr<uint8_t>(0));
  }
#endif
  record_scalar(p, done, n, image.ptr<uint8_t>(0));
  return image;
}

double SensorModel::noise_std_dn(double electrons, double gain) const {
  return std::sqrt(electrons + spec_.read_noise_e * spec_.read_noise_e) * gain / spec_.electrons_per_dn;
}

}  // namespace pllvo::synth
