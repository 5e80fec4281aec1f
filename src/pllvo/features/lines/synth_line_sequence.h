#pragma once
// Synthetic sequences (`pllvo synth`, docs/synth.md) as seen by the line evaluation: each frame's
// image with its true segments and their contrast, plus what places any point of a true edge in
// any frame (camera, poses, the 3-D edges), so tracked lines can be scored against the truth.
// Read from a `pllvo synth --lines` output folder, or rendered in memory by a synth::Generator.
#include <filesystem>
#include <map>
#include <vector>

#include <Eigen/Geometry>

#include "pllvo/camera/camera_model.h"
#include "pllvo/features/lines/detection_score.h"
#include "pllvo/synth/generator.h"

namespace pllvo::lines {

struct Edge3d {
  Eigen::Vector3d a, b;  ///< world frame, metres
};

struct SynthLineSequence {
  std::vector<TruthFrame> frames;  ///< truth ids = 3-D edge ids; contrast per segment
  std::vector<size_t> indices;     ///< index of each frame in the full sequence
  std::vector<Eigen::Isometry3d, Eigen::aligned_allocator<Eigen::Isometry3d>> T_world_cam;  ///< per frame
  camera::CameraPtr camera;
  std::map<int, Edge3d> edges;

  /// The point of edge `id` seen at pixel `uv` of frame k: the edge's point closest to the
  /// pixel's ray. False when the edge is unknown or (nearly) parallel to the ray.
  bool edge_point(size_t k, int id, const Eigen::Vector2d& uv, Eigen::Vector3d& X_world) const;
  /// Pixel of a world point in frame k; false behind the camera or outside the image.
  bool project(size_t k, const Eigen::Vector3d& X_world, Eigen::Vector2d& uv) const;
};

/// Which frames to take: first, first + step, ... (at most `count`; 0 = to the end).
struct SynthFrameSelection {
  size_t first = 0;
  size_t count = 0;
  size_t step = 1;
};

/// Reads cam0 of a `pllvo synth --lines` output folder: images (mav0/cam0/data.csv), true
/// segments (mav0/cam0/lines/<ns>.csv), 3-D edges (mav0/lines3d.csv), camera (sensor.yaml) and
/// poses (state_groundtruth_estimate0). InputError naming the file (and line) when anything is
/// missing or malformed, e.g. a folder written without --lines.
SynthLineSequence load_synth_line_sequence(const std::filesystem::path& root, const SynthFrameSelection& select = {});

/// Renders the frames `indices` of a generator (cam0, with line truth) in memory.
SynthLineSequence render_synth_line_sequence(synth::Generator& generator, const std::vector<size_t>& indices);

}  // namespace pllvo::lines
