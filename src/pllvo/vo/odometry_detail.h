#pragma once
// Small helpers shared by the files that implement Odometry (odometry*.cpp); not part of its interface.
#include <algorithm>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "pllvo/vo/keyframe_processor.h"
#include "pllvo/vo/line_mapper.h"

namespace pllvo::vo::odometry_detail {

inline Eigen::Vector2d to_eigen(const cv::Point2f& p) { return {p.x, p.y}; }

inline int count_mapped(const std::vector<TrackedPoint>& tracks) {
  return static_cast<int>(
      std::count_if(tracks.begin(), tracks.end(), [](const TrackedPoint& t) { return t.point != kNoId; }));
}

inline size_t count_mapped_lines(const std::vector<TrackedLine>& lines) {
  return static_cast<size_t>(
      std::count_if(lines.begin(), lines.end(), [](const TrackedLine& l) { return l.line != kNoId; }));
}

}  // namespace pllvo::vo::odometry_detail
