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

/// The ideal pinhole image: larger than the camera image so that it covers the distorted
/// camera's whole field of view. Only the pixels the camera samples are drawn: columns
/// [row_begin, row_end) of each row except [hole_begin, hole_end) (under barrel distortion
/// the rows near the top and bottom are needed only towards the corners).
struct IdealView {
  int width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  std::vector<int> row_begin, row_end, hole_begin, hole_end;

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
  void render(const Scene& scene, const RadianceState& radiance, const Eigen::Isometry3d& T_cam_world,
              float gain, bool with_ids = true);

  const cv::Mat& radiance() const { return radiance_; }        ///< CV_32F
  const cv::Mat& inverse_depth() const { return inv_depth_; }  ///< CV_32F, 1/z; 0 where empty
  const cv::Mat& quad_ids() const { return ids_; }  ///< CV_32S; -1 where empty (last render with ids)

  struct QuadShading;  ///< per-quad shading constants (internal)

 private:
  void draw_quad(const Quad& quad, int index, const MipTexture& tex, const Eigen::Isometry3d& T_cam_world,
                 float gain);

  IdealView view_;
  double near_;
  cv::Mat radiance_, inv_depth_, ids_;
  std::vector<std::pair<double, int>> order_;
  bool avx2_ = false;
  bool with_ids_ = true;
};

}  // namespace pllvo::synth
