#pragma once
// Image formation on the sensor: optical blur, vignetting, exposure and gain, photon and
// read noise, full-well clipping and 8-bit quantisation.
#include <cstdint>

#include <opencv2/core.hpp>

#include "pllvo/synth/spec.h"

namespace pllvo::synth {

class SensorModel {
 public:
  /// `bearings`: unit bearing per pixel (CV_32FC3), for the cos^4 vignetting.
  SensorModel(const SensorSpec& spec, const cv::Mat& bearings);

  /// Electrons collected per pixel (CV_32F, clipped at the full well) from scene radiance
  /// already blurred by the optics: radiance * light * vignetting * exposure * sensitivity.
  void electrons(const cv::Mat& radiance, double light, double exposure_ms, cv::Mat& out) const;
  /// Noise-free digital numbers (CV_32F, clipped to [0, 255]).
  cv::Mat expected_dn(const cv::Mat& electrons, double gain) const;
  /// The recorded 8-bit image from blurred radiance (CV_32F, camera size), in one pass:
  /// electrons as electrons() gives them, photon and read noise, gain, rounding to the
  /// nearest DN and clipping to [0, 255]. Photon noise is Poisson; it is drawn as a Gaussian
  /// of the same mean and variance (the counts here are >= ~50 e-, where the two agree).
  /// The Gaussian comes from a counter-based hash of (seed, pixel) through a 4096-segment
  /// piecewise-linear inverse normal CDF: exact in the core, tails cut at 3.9 sigma.
  cv::Mat record(const cv::Mat& radiance, double light, double exposure_ms, double gain, uint64_t noise_seed,
                 bool noise) const;
  /// Standard deviation in DN of a pixel collecting `electrons` (before quantisation).
  double noise_std_dn(double electrons, double gain) const;

  /// Optical point-spread function (Gaussian), applied to the camera-resolution radiance.
  void blur(cv::Mat& radiance) const;
  const cv::Mat& vignetting() const { return vignetting_; }

 private:
  SensorSpec spec_;
  cv::Mat vignetting_;
  bool avx2_ = false;
};

}  // namespace pllvo::synth
