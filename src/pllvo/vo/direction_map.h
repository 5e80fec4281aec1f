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

  /// The direction of each segment (index in directions(), -1: none) for a camera with
  /// rotation R_cam_world: residual below gate_px for one direction only. `focal`: pixels
  /// per normalised unit.
  std::vector<int> associate(const std::vector<DirectionSegment>& segments, const Eigen::Matrix3d& R_cam_world,
                             double focal) const;

  /// Proposes the directions that segments without one share (vanishing points supported by
  /// min_support distinct segments, min_separation_deg from the known and proposed directions;
  /// with orthogonal_only, perpendicular to the known ones), placed in the world by
  /// R_cam_world; a proposal becomes known once seen in confirm_frames frames (the proposing
  /// one included) within confirm_frames + 2 calls. Returns how many became known.
  int discover(const std::vector<DirectionSegment>& segments, const Eigen::Matrix3d& R_cam_world, double focal);

 private:
  struct Pending {
    Eigen::Vector3d direction;
    int seen = 1;  ///< frames with min_support segments on it, the proposing one included
    int age = 0;   ///< calls since the proposal
  };

  int max_directions() const;
  bool separate(const Eigen::Vector3d& d) const;
  bool orthogonal_to_known(const Eigen::Vector3d& d) const;
  /// With count_frame, counts the frame for each proposal (segments: `candidates`, those on a
  /// proposal are removed from it); then makes the confirmed ones known and drops the stale
  /// ones. Returns how many became known.
  int confirm_pending(const std::vector<DirectionSegment>& segments, std::vector<size_t>& candidates,
                      const Eigen::Matrix3d& R_cam_world, double focal, bool count_frame);

  DirectionConfig config_;
  std::vector<Eigen::Vector3d> directions_;  ///< unit, world frame; d and -d are one direction
  std::vector<Pending> pending_;
};

/// The directions one image shows alone (camera frame): those a new map finds in it when a
/// single frame confirms them (orthogonal_only: a Manhattan frame, three at most).
std::vector<Eigen::Vector3d> image_directions(const std::vector<DirectionSegment>& segments, double focal,
                                              DirectionConfig config);

}  // namespace pllvo::vo
