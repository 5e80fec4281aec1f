#pragma once
// Draws a scene into an ideal (distortion-free) pinhole image with a z-buffer: each quad
// facing the camera is clipped at the near plane, scan-converted (pixel centres inside the
// polygon), and textured through the plane's homography with trilinear mip-mapping.
// Inverse depth is linear in the pixel coordinates of a plane, so it is exact per pixel.
// With supersampling each pixel is the mean of f x f samples: a camera pixel integrates light
// over its area, and one sample at its centre draws stair steps along edges and broken dashes
// along surfaces thinner than a pixel, corners that slide along the edge as the camera moves.
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "pllvo/synth/radiance.h"
#include "pllvo/synth/scene.h"

namespace pllvo::synth {

/// A set of pixels as runs of columns per row: the runs of row y are [begin[k], end[k]) for
/// k in [first[y], first[y + 1]).
struct RowRuns {
  std::vector<int> first, begin, end;

  /// The non-zero pixels of a CV_8U mask.
  static RowRuns from_mask(const cv::Mat& mask);
  size_t pixels() const;
};

/// The ideal pinhole image: larger than the camera image so that it covers the distorted
/// camera's whole field of view (plus a margin for motion blur). Only the pixels the
/// camera samples are drawn (`drawn`; under barrel distortion the rows near the top and
/// bottom are needed only towards the corners).
struct IdealView {
  int width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  RowRuns drawn;

  /// Pixel of a point in the camera frame (z > 0).
  Eigen::Vector2d project(const Eigen::Vector3d& p) const {
    return {fx * p.x() / p.z() + cx, fy * p.y() / p.z() + cy};
  }
};

class Rasterizer {
 public:
  /// `simd`: use AVX2 when the CPU has it (the scalar path gives the same image, slower).
  /// `supersample`: samples per pixel side (1: one sample at the pixel centre).
  Rasterizer(IdealView view, double near_m, bool simd = true, int supersample = 1);

  const IdealView& view() const { return view_; }

  /// Renders from camera pose T_cam_world; radiance is multiplied by `gain`. Quad ids are
  /// written only `with_ids` (they cost memory traffic and only the ground truth needs them).
  /// Only the pixels of `pixels` are cleared and drawn (default: the view's `drawn`), so a
  /// second call with other pixels and the same pose extends the image.
  void render(const Scene& scene, const RadianceState& radiance, const Eigen::Isometry3d& T_cam_world,
              float gain, bool with_ids = true, const RowRuns* pixels = nullptr);

  const cv::Mat& radiance() const { return radiance_; }        ///< CV_32F, mean over the samples
  /// CV_32F, 1/z; 0 where empty. Supersampled: of the nearest sample (the largest 1/z).
  const cv::Mat& inverse_depth() const { return inv_depth_; }
  /// CV_32S; -1 where empty (last render with ids). Supersampled: of the nearest sample.
  const cv::Mat& quad_ids() const { return ids_; }

  struct QuadShading;  ///< per-quad shading constants (internal)

 private:
  void draw_quad(const Quad& quad, int index, const MipTexture& tex, const Eigen::Isometry3d& T_cam_world,
                 float gain, const RowRuns& pixels);
  /// Pixels of `runs` (of view_) as runs of the sample grid.
  RowRuns sample_runs(const RowRuns& runs) const;
  /// Averages the samples of each pixel of `runs` into the output images.
  void resolve(const RowRuns& runs);

  IdealView view_;
  double near_;
  int factor_ = 1;
  IdealView sample_view_;  ///< the view scaled by factor_ (view_ itself when 1)
  cv::Mat radiance_, inv_depth_, ids_;
  cv::Mat sample_radiance_, sample_inv_depth_, sample_ids_;  ///< share the outputs' data when factor_ is 1
  std::vector<std::pair<double, int>> order_;
  bool avx2_ = false;
  bool with_ids_ = true;
};

}  // namespace pllvo::synth
