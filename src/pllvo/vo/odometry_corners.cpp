// Odometry: the tracker's own corners between keyframes (pose.frame_corners, frame_corners.h).
#include <spdlog/spdlog.h>

#include "pllvo/common/statistics.h"
#include "pllvo/vo/odometry.h"
#include "pllvo/vo/odometry_detail.h"

namespace pllvo::vo {

using namespace odometry_detail;

bool Odometry::uses_frame_corners() const {
  // Monocular only: a metric map's keyframes bring stereo or depth points, and two-frame depths
  // made its live poses worse (docs/vo.md).
  return makes_provisional_points() && config_.pose.frame_corners > 0 && !metric();
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

void Odometry::refresh_corners(const cv::Mat& image, int map_inliers) {
  if (!uses_frame_corners()) return;
  ScopedTimer t(stats_, "frame_corners");
  for (FrameCorner& c : corners_)
    c.position = triangulate_point(camera_, {c.T_world_first, T_world_work_}, {c.first_px, to_eigen(c.px)},
                                   config_.geometry.point_triangulation);
  const int room = config_.pose.frame_corners - static_cast<int>(corners_.size());
  if (map_inliers >= config_.run.starving_points || room <= 0) return;
  std::vector<cv::Point2f> occupied;
  for (const TrackedPoint& tp : tracks_) occupied.push_back(tp.px);
  for (const FrameCorner& c : corners_) occupied.push_back(c.px);
  const auto found = detect_free_corners(image, occupied, room, config_.pose.frame_corner_spacing_px);
  for (const auto& p : found) corners_.push_back({p, T_world_work_, to_eigen(p), std::nullopt});
  stats_.add_count("frame_corners_found", static_cast<long long>(found.size()));
  spdlog::debug("{} corners found between keyframes ({} followed)", found.size(), corners_.size());
}

}  // namespace pllvo::vo
