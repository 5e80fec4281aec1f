#include "pllvo/vo/stereo_depth.h"

#include <algorithm>
#include <cmath>

namespace pllvo::vo {

StereoDepths stereo_depths(const PointTracker& klt, const ImagePyramid& left_pyramid, const cv::Mat& left,
                           const cv::Mat& right, const std::vector<cv::Point2f>& points, const Pinhole& camera,
                           double baseline, double offset_px, const StereoRowMatchConfig& row,
                           const geometry::StereoTriangulationConfig& triangulation) {
  StereoDepths out;
  out.points.resize(points.size());
  out.right_px.assign(points.size(), cv::Point2f(NAN, NAN));
  if (right.empty() || points.empty()) return out;
  TrackResult tr = klt.track(left_pyramid, klt.build_pyramid(right), points);
  out.lk_rejected = tr.rejected;
  for (size_t k = 0; k < points.size(); ++k) {
    if (!tr.ok[k]) continue;
    if (row.min_horizontal_share > 0) {
      const auto x = refine_along_row(left, right, points[k], tr.points[k].x, row);
      if (!x) {
        ++out.row_rejects;
        continue;
      }
      tr.points[k] = cv::Point2f(*x, points[k].y);
    }
    // The measured disparity plus the pair's offset (the match itself stays as measured).
    const Eigen::Vector2d left_px(points[k].x, points[k].y);
    const Eigen::Vector2d right_corrected(tr.points[k].x - offset_px, tr.points[k].y);
    const auto p = triangulate_stereo(camera, baseline, left_px, right_corrected, triangulation);
    if (!p) {
      ++out.depth_rejects;
      continue;
    }
    ++out.matched;
    out.right_px[k] = tr.points[k];
    out.points[k] = p;
  }
  return out;
}

StereoDepths depth_image_depths(const cv::Mat& depth, const std::vector<cv::Point2f>& points, const Pinhole& camera,
                                double baseline, const DepthConfig& config,
                                const geometry::StereoTriangulationConfig& triangulation) {
  StereoDepths out;
  out.points.resize(points.size());
  out.right_px.assign(points.size(), cv::Point2f(NAN, NAN));
  if (depth.empty()) return out;
  for (size_t k = 0; k < points.size(); ++k) {
    const float d = depth_at(depth, points[k], config);
    if (d == 0) continue;
    if (!std::isfinite(d)) {
      ++out.edge_rejects;
      continue;
    }
    const cv::Point2f right(points[k].x - static_cast<float>(camera.fx * baseline / d), points[k].y);
    const auto p = triangulate_stereo(camera, baseline, Eigen::Vector2d(points[k].x, points[k].y),
                                      Eigen::Vector2d(right.x, right.y), triangulation);
    if (!p) {
      ++out.depth_rejects;
      continue;
    }
    ++out.matched;
    out.right_px[k] = right;
    out.points[k] = p;
  }
  return out;
}

StereoRowMatchConfig stereo_row_match(const VoConfig& config) {
  StereoRowMatchConfig row;
  row.window_px = config.klt.window_px;
  row.min_horizontal_share = config.klt.stereo_min_horizontal_share;
  return row;
}

float depth_at(const cv::Mat& depth, const cv::Point2f& px, const DepthConfig& config) {
  const int x = static_cast<int>(std::lround(px.x)), y = static_cast<int>(std::lround(px.y));
  if (x < 0 || y < 0 || x >= depth.cols || y >= depth.rows) return 0;
  const auto valid = [&](float d) { return std::isfinite(d) && d >= config.min_m && d <= config.max_m; };
  const float d = depth.at<float>(y, x);
  if (!valid(d)) return 0;
  float lo = d, hi = d;
  for (int v = std::max(0, y - 1); v <= std::min(depth.rows - 1, y + 1); ++v)
    for (int u = std::max(0, x - 1); u <= std::min(depth.cols - 1, x + 1); ++u) {
      const float n = depth.at<float>(v, u);
      if (valid(n)) lo = std::min(lo, n), hi = std::max(hi, n);
    }
  return hi - lo > config.max_local_spread * d ? NAN : d;
}

}  // namespace pllvo::vo
