#pragma once
// The path from the ideal pinhole rendering to the camera's pixels: an ideal view large
// enough for the lens's whole field, a remap table built from the camera model (each
// camera pixel samples the ideal image where its ray lands), and per-pixel bearings.
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "pllvo/camera/camera_model.h"
#include "pllvo/synth/rasterizer.h"

namespace pllvo::synth {

/// Pixels of the ideal view within `margin` (in x and in y) of the drawn ones: what a render
/// must cover when motion blur samples it up to `margin` pixels away from the camera's rays.
struct BlurRegion {
  int margin = 0;
  RowRuns all;   ///< the drawn pixels and the margin
  RowRuns ring;  ///< the margin only
};

class LensModel {
 public:
  /// Widest margin around the drawn pixels (the ideal view has room for it).
  static constexpr int kMaxBlurMargin = 48;

  /// Unprojects every camera pixel once (Newton per pixel); InternalError when the model
  /// cannot be inverted somewhere in the image.
  explicit LensModel(const camera::CameraModel& camera);

  const IdealView& ideal_view() const { return view_; }
  /// Camera image (CV_32F, camera size) from an ideal image (CV_32F, ideal size), bilinear
  /// (AVX2 when the CPU has it; both paths give the same result).
  void distort(const cv::Mat& ideal, cv::Mat& image) const;
  /// Where each camera pixel lands in the ideal image (CV_32FC2: x, y).
  const cv::Mat& ideal_coordinates() const { return ideal_xy_; }
  /// Unit bearing of each camera pixel in the camera frame (CV_32FC3).
  const cv::Mat& bearings() const { return bearings_; }
  /// The narrowest blur region with margin >= shift_px (the widest when none is).
  const BlurRegion& blur_region(double shift_px) const;

 private:
  IdealView view_;
  cv::Mat ideal_xy_, bearings_;
  std::vector<BlurRegion> blur_regions_;  // by increasing margin
  // Bilinear taps per camera pixel: top-left ideal pixel index and the fractions.
  std::vector<int32_t> tap_index_;
  std::vector<float> tap_fx_, tap_fy_;
  bool avx2_ = false;
};

}  // namespace pllvo::synth
