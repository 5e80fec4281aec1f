#pragma once
// Per-frame ground truth from the scene: the visible pieces of its 3-D edges in the camera
// image (straight edges bend under lens distortion, so each visible run is split into
// straight pieces within a tolerance) and the depth of every pixel.
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "pllvo/camera/camera_model.h"
#include "pllvo/synth/lens.h"
#include "pllvo/synth/rasterizer.h"
#include "pllvo/synth/scene.h"

namespace pllvo::synth {

struct TruthSegment {
  int id = 0;  ///< SceneEdge id: the same 3-D edge keeps its id in every frame
  EdgeKind kind = EdgeKind::geometric;
  Eigen::Vector2d a, b;  ///< endpoints in camera pixels (distorted image)
  /// Where the piece lies on the 3-D edge: point(t) = edge.a + t * (edge.b - edge.a).
  double t0 = 0, t1 = 1;
  /// Brightness difference across the segment in the noise-free image (DN); for thin
  /// lines, the line against its sides.
  float contrast = 0;
};

struct SegmentOptions {
  double min_length_px = 8;     ///< shorter pieces are dropped
  double max_deviation_px = 0.5;  ///< straight pieces follow the distorted edge this closely
  double near_m = 0.05;
};

/// Visible pieces of every scene edge, seen from T_cam_world. Visibility is decided per
/// sample (<= 1 ideal pixel apart) against what the rasterizer drew: a sample is visible
/// when one of the edge's own quads is seen in its 3x3 pixel neighbourhood (so visibility
/// is exact to about one pixel at occlusion boundaries).
std::vector<TruthSegment> visible_segments(const Scene& scene, const Eigen::Isometry3d& T_cam_world,
                                           const camera::CameraModel& camera, const Rasterizer& raster,
                                           const SegmentOptions& options = {});

/// Fills each segment's contrast from a noise-free image (CV_32F, camera size).
void measure_contrast(const cv::Mat& clean, std::vector<TruthSegment>& segments);

/// Depth (z along the optical axis, metres; 0 where nothing) of each camera pixel: the
/// surface the rasterizer saw nearest to the pixel's ray, intersected exactly with the ray.
cv::Mat depth_image(const Scene& scene, const Eigen::Isometry3d& T_cam_world, const LensModel& lens,
                    const Rasterizer& raster);

}  // namespace pllvo::synth
