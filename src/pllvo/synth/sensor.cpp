#include "pllvo/synth/sensor.h"

#include <cmath>

#include <opencv2/imgproc.hpp>

namespace pllvo::synth {

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

cv::Mat SensorModel::record(const cv::Mat& electrons, double gain, uint64_t noise_seed, bool noise) const {
  cv::Mat image;
  const double to_dn = gain / spec_.electrons_per_dn;
  if (!noise) {
    electrons.convertTo(image, CV_8U, to_dn);
    return image;
  }
  // Variance = signal (shot noise) + read noise^2.
  cv::Mat sigma;
  cv::add(electrons, spec_.read_noise_e * spec_.read_noise_e, sigma);
  cv::sqrt(sigma, sigma);
  cv::Mat n(electrons.size(), CV_32F);
  cv::RNG rng(noise_seed);
  rng.fill(n, cv::RNG::NORMAL, 0.0, 1.0);
  cv::Mat e = electrons + sigma.mul(n);
  e.convertTo(image, CV_8U, to_dn);  // rounds to nearest, saturates to [0, 255]
  return image;
}

double SensorModel::noise_std_dn(double electrons, double gain) const {
  return std::sqrt(electrons + spec_.read_noise_e * spec_.read_noise_e) * gain / spec_.electrons_per_dn;
}

}  // namespace pllvo::synth
