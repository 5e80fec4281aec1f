#pragma once
// Motion blur from one render: each camera pixel averages the render along the image path
// of the scene point it sees, over (a part of) the exposure.
//
// The render's depth gives the scene point behind each camera pixel at the render's time;
// projecting it with the camera poses at the start and end of the sub-exposure gives its
// image motion d(tau) (a straight segment: the poses are milliseconds apart). At time tau
// the pixel at x sees what the render shows at x - d(tau) (the motion inverted to first
// order), so the pixel records the mean of the render along that segment, sampled every
// `step_px` (bilinear taps). This is exact where the image motion is locally uniform
// (rotation, planar surfaces) and approximate across depth steps, where the render lacks the
// background uncovered during the exposure; splitting the exposure over several renders
// shortens each path and so narrows that band. The samples land in the lens's ideal image,
// so this replaces LensModel::distort for the frame.
#include <cstdint>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "pllvo/synth/lens.h"
#include "pllvo/synth/rasterizer.h"

namespace pllvo::synth {

class FlowBlur {
 public:
  /// `step_px`: spacing of the samples along a path (ideal pixels); `max_samples` caps their
  /// number per pixel. `simd`: AVX2 when the CPU has it (the scalar path gives the same image).
  FlowBlur(const LensModel& lens, double step_px, int max_samples, bool simd = true);

  /// image = (add ? image : 0) + weight * (the render averaged along each camera pixel's path
  /// from the sub-exposure's start to its end). `T_start_render`, `T_end_render` map the
  /// render's camera frame to the camera frame at the start and end of the sub-exposure.
  /// `render` must have drawn `region.all`; paths are cut at its margin. `image`: CV_32F,
  /// camera size. Returns the mean number of samples per camera pixel.
  double accumulate(const Rasterizer& render, const Eigen::Isometry3d& T_start_render,
                    const Eigen::Isometry3d& T_end_render, float weight, const BlurRegion& region, cv::Mat& image,
                    bool add) const;

  /// Per-call constants of accumulate() (internal).
  struct Pass;

 private:
  int width_ = 0, height_ = 0;  // camera image
  int ideal_width_ = 0, ideal_height_ = 0;
  float fx_ = 0, fy_ = 0, cx_ = 0, cy_ = 0;
  float step_px_ = 1;
  int max_samples_ = 1;
  // Where each camera pixel lands in the ideal image (its ray and the depth it uses follow
  // from that: the tables are kept small because this pass is bound by memory traffic).
  std::vector<float> x_, y_;
  bool avx2_ = false;
};

}  // namespace pllvo::synth
