#pragma once
// Pre-filtering for line detection on dark and noisy images. Two measurements of the frame
// choose what to do, so clean frames pay nothing:
//  - brightness (a high percentile of the intensities): a dark frame is contrast-stretched, so
//    the fixed gradient threshold of EdgeDrawing still finds its edges;
//  - noise (robust Immerkaer estimate: median |Laplacian-like mask| over the frame): a noisy frame
//    gets a stronger Gaussian blur and a higher gradient threshold, so noise does not break
//    straight edges into jagged pieces or create short spurious ones.
#include <opencv2/core.hpp>

#include "pllvo/common/yaml_config.h"

namespace pllvo::lines {

struct PrefilterConfig {
  bool enabled = true;
  /// Brightness is measured at this percentile of the intensities (robust to a few hot pixels).
  double bright_percentile = 0.99;
  /// Frames whose bright percentile is below this level (grey levels) are contrast-stretched.
  double dark_level = 120.0;
  /// Stretch target: the frame's [1% percentile, bright percentile] is mapped to [0, target_level].
  double target_level = 220.0;
  /// Largest gain of the stretch (noise is amplified by the same gain).
  double max_gain = 10.0;
  /// Noise (grey levels, after the stretch) up to which the base smoothing is used.
  double clean_noise_sigma = 2.5;
  /// Extra Gaussian sigma (px) per grey level of noise above clean_noise_sigma.
  double sigma_per_noise = 0.15;
  /// Largest Gaussian sigma (px).
  double max_sigma = 2.5;
  /// Gradient threshold floor from noise: threshold >= gradient_per_noise * noise / sigma.
  /// EdgeDrawing's Prewitt |gx|+|gy| on blurred white noise has roughly this scale.
  double gradient_per_noise = 4.0;
  /// Rows sampled for the noise estimate (every n-th row), for speed.
  int noise_row_step = 4;

  void load(const ConfigNode& node);
};

/// What the prefilter decided for one frame.
struct PrefilterResult {
  cv::Mat image;                ///< 8-bit image handed to EdgeDrawing (may share the input's data)
  double gain = 1.0;            ///< contrast gain applied (1 = unchanged)
  double bright_level = 0.0;    ///< measured bright percentile of the input
  double noise_sigma = 0.0;     ///< estimated noise of `image` (grey levels)
  double blur_sigma = 1.0;      ///< Gaussian sigma for EdgeDrawing
  int gradient_threshold = 20;  ///< gradient threshold for EdgeDrawing
};

/// Robust noise standard deviation of an 8-bit image (grey levels), after Immerkaer (1996):
/// the 3x3 mask [1 -2 1; -2 4 -2; 1 -2 1] cancels smooth structure; the median of its absolute
/// response (not the mean) keeps edges from inflating the estimate.
double estimate_noise_sigma(const cv::Mat& gray, int row_step = 1);

/// Decides and applies the pre-filter. `base_sigma` and `base_gradient_threshold` are the
/// EdgeDrawing settings for clean, well-exposed frames.
PrefilterResult prefilter_for_lines(const cv::Mat& gray, const PrefilterConfig& config, double base_sigma,
                                    int base_gradient_threshold);

}  // namespace pllvo::lines
