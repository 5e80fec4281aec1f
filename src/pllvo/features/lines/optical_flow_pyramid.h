#pragma once
// An image pyramid for pyramidal Lucas-Kanade (cv::buildOpticalFlowPyramid, with derivatives),
// built once per frame and shared by every tracker that uses it: frame k+1's pyramid is the
// "next" pyramid now and becomes the "prev" pyramid at the following frame, so each frame's
// pyramid and derivatives are computed exactly once.
#include <algorithm>
#include <cmath>
#include <vector>

#include <opencv2/core.hpp>

namespace pllvo::lines {

/// Smaller over larger eigenvalue of a window's structure tensor [sxx sxy; sxy syy] (sums of
/// gradient products): ~0 on a straight edge, where LK cannot see motion along it (the aperture
/// problem), up to 1 at a corner or blob; 0 on a flat window.
inline double structure_tensor_ratio(double sxx, double sxy, double syy) {
  const double trace = sxx + syy;
  if (trace <= 0.0) return 0.0;
  const double root = std::sqrt(std::max(0.0, 0.25 * (sxx - syy) * (sxx - syy) + sxy * sxy));
  return (0.5 * trace - root) / (0.5 * trace + root);
}

class OpticalFlowPyramid {
 public:
  OpticalFlowPyramid() = default;
  /// `window`: the LK window it will serve (sets the border padding); `max_level`: 0 = only
  /// the full-resolution image. `normalized_mean` > 0 scales the image so that its mean grey
  /// level is that value before the pyramid is built: LK assumes constant brightness, and a
  /// flickering lamp or an exposure change scales the whole frame (0 = the image as it is).
  /// Throws InputError for an empty or non-8-bit-gray image.
  OpticalFlowPyramid(const cv::Mat& gray, cv::Size window, int max_level, double normalized_mean = 0.0);

  bool empty() const { return levels_.empty(); }
  const std::vector<cv::Mat>& levels() const { return levels_; }
  cv::Size window() const { return window_; }
  int max_level() const { return max_level_; }
  cv::Size image_size() const { return size_; }
  double gain() const { return gain_; }  ///< brightness gain applied (1 = none)

 private:
  std::vector<cv::Mat> levels_;
  cv::Size window_;
  int max_level_ = 0;
  cv::Size size_;
  double gain_ = 1.0;
};

}  // namespace pllvo::lines
