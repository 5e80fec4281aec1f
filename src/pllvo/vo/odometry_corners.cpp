// Odometry: the tracker's own corners between keyframes (pose.frame_corners, frame_corners.h).
#include <spdlog/spdlog.h>

#include "pllvo/common/statistics.h"
#include "pllvo/vo/odometry.h"
#include "pllvo/vo/odometry_detail.h"
#include "pllvo/vo/stereo_depth.h"

namespace pllvo::vo {

using namespace odometry_detail;

bool Odometry::uses_frame_corners() const {
  // pose.frame_corners is the mode's: pose.stereo_frame_corners for a metric map (VoConfig::for_mode).
  return makes_provisional_points() && config_.pose.frame_corners > 0;
}

void Odometry::follow_corners(const ImagePyramid& pyramid, const geometry::Pose& T_pred_world) {
  if (corners_.empty() || previous_pyramid_.empty()) return;
  ScopedTimer t(stats_, "frame_corners");
  std::vector<cv::Point2f> from, predicted;
  for (const FrameCorner& c : corners_) {
    from.push_back(c.px);
    predicted.push_back(klt_seed(c.position ? &*c.position : nullptr, c.px, T_pred_world));
  }
  const TrackResult tr = tracker_.track_with_contrast_fallback(previous_pyramid_, pyramid, from, &predicted);
  std::vector<FrameCorner> kept;
  for (size_t i = 0; i < corners_.size(); ++i) {
    if (!tr.ok[i]) continue;
    kept.push_back(corners_[i]);
    kept.back().px = tr.points[i];
  }
  corners_ = std::move(kept);
}

void Odometry::refresh_corners(const ImagePyramid& pyramid, const cv::Mat& right, int map_inliers) {
  if (!uses_frame_corners()) return;
  ScopedTimer t(stats_, "frame_corner_search");
  if (metric()) {
    // A metric corner keeps the position measured where it was found; one the pose refused goes.
    std::erase_if(corners_, [](const FrameCorner& c) { return !c.position; });
  } else {
    for (FrameCorner& c : corners_)
      c.position = triangulate_point(camera_, {c.T_world_first, T_world_work_}, {c.first_px, to_eigen(c.px)},
                                     config_.geometry.point_triangulation);
  }
  const int room = config_.pose.frame_corners - static_cast<int>(corners_.size());
  if (map_inliers >= config_.run.starving_points || room <= 0) return;
  std::vector<cv::Point2f> occupied;
  for (const TrackedPoint& tp : tracks_) occupied.push_back(tp.px);
  for (const FrameCorner& c : corners_) occupied.push_back(c.px);
  const auto found = detect_free_corners(pyramid.image, occupied, room, config_.pose.frame_corner_spacing_px);
  std::vector<std::optional<Eigen::Vector3d>> positions(found.size());
  if (metric()) {
    ScopedTimer depth_timer(stats_, "frame_corner_depth");
    positions = measure_corner_depths(pyramid, right, found);
  }
  int added = 0;
  for (size_t k = 0; k < found.size(); ++k) {
    if (metric() && !positions[k]) continue;
    corners_.push_back({found[k], T_world_work_, to_eigen(found[k]), positions[k]});
    ++added;
  }
  stats_.add_count("frame_corners_found", added);
  spdlog::debug("{} corners found between keyframes ({} followed)", added, corners_.size());
}

std::vector<std::optional<Eigen::Vector3d>> Odometry::measure_corner_depths(const ImagePyramid& pyramid,
                                                                            const cv::Mat& right,
                                                                            const std::vector<cv::Point2f>& found) {
  // The same measurement as a keyframe's new points (KeyframeProcessor::stereo_points, depth_points).
  std::vector<std::optional<Eigen::Vector3d>> out =
      depth() ? depth_image_depths(frame_depth_, found, camera_, config_.depth.virtual_baseline_m, config_.depth,
                                   config_.geometry.stereo)
                    .points
              : stereo_depths(tracker_, pyramid, pyramid.image, right, found, camera_, rectifier_.baseline(),
                              stereo_offset_px_, stereo_row_match(config_), config_.geometry.stereo)
                    .points;
  for (auto& p : out)
    if (p) p = T_world_work_ * *p;
  return out;
}

}  // namespace pllvo::vo
