#pragma once
// Metric depth of image points in one frame, from its rectified right image or its depth image.
// A keyframe's new points (KeyframeProcessor) and the tracker's own corners between keyframes
// (Odometry::refresh_corners) use the same matching, so both get the same depths.
#include <optional>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "pllvo/geometry/geometry_config.h"
#include "pllvo/vo/geometry_adapter.h"
#include "pllvo/vo/point_tracker.h"
#include "pllvo/vo/stereo_row_match.h"
#include "pllvo/vo/vo_config.h"

namespace pllvo::vo {

struct StereoDepths {
  std::vector<std::optional<Eigen::Vector3d>> points;  ///< in the left rectified camera, per input point
  std::vector<cv::Point2f> right_px;  ///< the match as measured (NaN where none): the BA's observation
  TrackResult::Rejections lk_rejected;  ///< lost by the left-to-right LK
  int row_rejects = 0;    ///< lost by the refinement along the row (too little horizontal texture)
  int depth_rejects = 0;  ///< refused by the triangulation's checks
  int edge_rejects = 0;   ///< depth image: on a depth edge (depth_at)
  int matched = 0;
};

/// Left-right matches of `points` by LK from `left` (its pyramid for `klt`) into `right`,
/// finished along the row (`row`, min_horizontal_share 0: not), triangulated with the true
/// disparity taken as the measured one plus `offset_px` (the pair's offset the window BA estimates).
StereoDepths stereo_depths(const PointTracker& klt, const ImagePyramid& left_pyramid, const cv::Mat& left,
                           const cv::Mat& right, const std::vector<cv::Point2f>& points, const Pinhole& camera,
                           double baseline, double offset_px, const StereoRowMatchConfig& row,
                           const geometry::StereoTriangulationConfig& triangulation);

/// The same from a depth image registered to the left camera: each point's depth (depth_at) as
/// the disparity of a virtual pair of `baseline` (its right pixel u - f b / d, the BA's
/// observation), triangulated by the same checks; none where the depth image has no measurement.
StereoDepths depth_image_depths(const cv::Mat& depth, const std::vector<cv::Point2f>& points, const Pinhole& camera,
                                double baseline, const DepthConfig& config,
                                const geometry::StereoTriangulationConfig& triangulation);

/// The row refinement's settings from the config (klt.window_px, klt.stereo_min_horizontal_share).
StereoRowMatchConfig stereo_row_match(const VoConfig& config);

/// The depth image's value (metres) at the pixel nearest `px` when it is a measurement in the
/// config's range, else 0; NaN when its 3x3 neighbourhood's valid depths spread by more than
/// max_local_spread of it (a depth edge).
float depth_at(const cv::Mat& depth, const cv::Point2f& px, const DepthConfig& config);

}  // namespace pllvo::vo
