#pragma once
// 3-D directions that many image lines share (a room's verticals, the horizontals of its
// walls and shelves), kept in the world frame. A segment parallel to a known direction
// constrains the camera's rotation alone, whatever the translation and the map's scale, so the
// rotation cannot drift with a map whose few points sit far away on one plane.
#include <vector>

#include <Eigen/Core>

#include "pllvo/vo/vo_config.h"

namespace pllvo::vo {

/// An image segment in normalised coordinates, with its length in pixels.
struct DirectionSegment {
  Eigen::Vector2d start, end;
  double length_px = 0;
};

class DirectionMap {
 public:
  explicit DirectionMap(DirectionConfig config = {}) : config_(config) {}

  const std::vector<Eigen::Vector3d>& directions() const { return directions_; }
  void clear() { directions_.clear(); }

  /// The direction of each segment (index in directions(), -1: none) for a camera with
  /// rotation R_cam_world: residual below gate_px for one direction only. `focal`: pixels
  /// per normalised unit.
  std::vector<int> associate(const std::vector<DirectionSegment>& segments, const Eigen::Matrix3d& R_cam_world,
                             double focal) const;

  /// Adds the directions that segments without one share (vanishing points supported by
  /// min_support distinct segments, min_separation_deg from the known directions; with
  /// orthogonal_only, perpendicular to them), placed in the world by R_cam_world. Returns how
  /// many were added.
  int discover(const std::vector<DirectionSegment>& segments, const Eigen::Matrix3d& R_cam_world, double focal);

 private:
  int max_directions() const;

  DirectionConfig config_;
  std::vector<Eigen::Vector3d> directions_;  ///< unit, world frame; d and -d are one direction
};

}  // namespace pllvo::vo
