#pragma once
// Synthetic test frames with exactly known line segments: non-overlapping filled convex polygons
// (rectangles, triangles, quadrilaterals) and ellipses (curved clutter, no true segment) on a
// textured background, rendered with 8x supersampling so every polygon edge is an anti-aliased
// step at a known sub-pixel position. Lighting variants scale the intensities down (dark) and
// add sensor noise, as low-light frames do. A sequence moves the whole scene by known rigid
// motions, for tracking. Used by the line tests and `pllvo lines-eval` until the synthetic
// sequence generator provides richer scenes.
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "pllvo/features/lines/detection_score.h"
#include "pllvo/features/lines/line_segment.h"

namespace pllvo::lines {

struct PolygonSceneConfig {
  int width = 752;
  int height = 480;
  int num_polygons = 14;
  double min_size_px = 50.0;  ///< polygon bounding-circle diameter range
  double max_size_px = 190.0;
  double min_contrast = 35.0;        ///< |polygon - background| grey levels at brightness 1
  double background_texture = 18.0;  ///< amplitude of the smooth background texture
  /// Amplitude of a fine (4 px grain) texture, as on carpet, wood or concrete: edges without
  /// any straight line that a detector must not report.
  double fine_texture = 10.0;
  /// Filled ellipses (curved edges, no true segment): line pieces fitted to them are false.
  int num_ellipses = 4;
  double brightness = 1.0;   ///< multiplies every intensity (0.12 = a dark frame)
  double noise_sigma = 2.0;  ///< additive Gaussian noise (grey levels, after the brightness)
  int supersample = 8;
  uint64_t seed = 1;
};

/// image: CV_8UC1; truth: every polygon edge (the part inside the image), id = edge number,
/// stable over a sequence.
using PolygonScene = TruthFrame;

PolygonScene render_polygon_scene(const PolygonSceneConfig& config);

/// A sequence of one scene moved rigidly: frame k shows the scene of frame 0 mapped by
/// motions[k] (frame-0 pixel -> frame-k pixel), with fresh noise per frame.
struct PolygonSequence {
  std::vector<PolygonScene> frames;
  std::vector<Eigen::Isometry2d> motions;
};
PolygonSequence render_polygon_sequence(const PolygonSceneConfig& config,
                                        const std::vector<Eigen::Isometry2d>& motions);

/// Lighting presets: "normal" (bright, noise 2), "dark" (brightness 0.12, noise 1.5 before
/// the stretch) and "noisy" (noise 8). InputError for another name.
PolygonSceneConfig polygon_lighting(const std::string& lighting, int width = 752, int height = 480);

/// The built-in detection suites: `frames` scenes of the given lighting, seeds 1..frames.
std::vector<PolygonScene> polygon_suite(const std::string& lighting, int frames, int width = 752,
                                        int height = 480);

/// The built-in tracking sequence: `frames` frames, the scene turning by `deg_per_frame` about
/// the image centre and shifting by `shift_per_frame` px per frame.
PolygonSequence polygon_tracking_sequence(const std::string& lighting, int frames, double deg_per_frame = 0.3,
                                          Eigen::Vector2d shift_per_frame = {1.5, -1.0}, uint64_t seed = 1);

}  // namespace pllvo::lines
