#pragma once
// Draws a scene into an ideal (distortion-free) pinhole image with a z-buffer: each quad
// facing the camera is clipped at the near plane, scan-converted (pixel centres inside the
// polygon), and textured through the plane's homography with trilinear mip-mapping.
// Inverse depth is linear in the pixel coordinates of a plane, so it is exact per pixel.
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
  Rasterizer(IdealView view, double near_m, bool simd = true);

  const IdealView& view() const { return view_; }

  /// Renders from camera pose T_cam_world; radiance is multiplied by `gain`. Quad ids are
  /// written only `with_ids` (they cost memory traffic and only the ground truth needs them).
  /// Only the pixels of `pixels` are cleared and drawn (default: the view's `drawn`), so a
  /// second call with other pixels and the same pose extends the image.
  void render(const Scene& scene, const RadianceState& radiance, const Eigen::Isometry3d& T_cam_world,
              float gain, bool with_ids = true, const RowRuns* pixels = nullptr);

  const cv::Mat& radiance() const { return radiance_; }        ///< CV_32F
  const cv::Mat& inverse_depth() const { return inv_depth_; }  ///< CV_32F, 1/z; 0 where empty
  const cv::Mat& quad_ids() const { return ids_; }  ///< CV_32S; -1 where empty (last render with ids)

  struct QuadShading;  ///< per-quad shading constants (internal)

 private:
  void draw_quad(const Quad& quad, int index, const MipTexture& tex, const Eigen::Isometry3d& T_cam_world,
                 float gain, const RowRuns& pixels);

  IdealView view_;
  double near_;
  cv::Mat radiance_, inv_depth_, ids_;
  std::vector<std::pair<double, int>> order_;
  bool avx2_ = false;
  bool with_ids_ = true;
};

}  // namespace pllvo::synth
