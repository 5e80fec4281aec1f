#pragma once
// Corners that the tracking thread finds itself, between keyframes, when a live map starves
// (pose.frame_corners). A keyframe takes 300-500 ms on a 2-core CPU; in a dark or fast turn the
// map's tracks die within a few frames of it. These corners are followed by KLT, triangulated
// from the tracked frame they were found in and the latest one, and join a starving frame's
// pose as provisional points do. They never enter the map nor a keyframe.
#include <optional>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "pllvo/geometry/pose.h"

namespace pllvo::vo {

struct FrameCorner {
  cv::Point2f px;                        ///< in the latest frame
  geometry::Pose T_world_first;          ///< the tracked frame it was found in...
  Eigen::Vector2d first_px;              ///< ...and where
  std::optional<Eigen::Vector3d> position;  ///< from the first and the latest tracked view
};

/// Up to `max_new` Shi-Tomasi corners of `image` (8-bit grey), at least `spacing_px` from
/// each other and from every point of `occupied`, the strongest first.
std::vector<cv::Point2f> detect_free_corners(const cv::Mat& image, const std::vector<cv::Point2f>& occupied,
                                             int max_new, double spacing_px);

}  // namespace pllvo::vo
