// KeyframeProcessor: starting and resuming map segments (a new segment after a loss, a monocular
// two-view start, a segment resumed at its scale) and relocalising a keyframe in the map.
#include "pllvo/vo/keyframe_processor.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include <spdlog/spdlog.h>

#include "pllvo/vo/stereo_row_match.h"

namespace pllvo::vo {
namespace {

Eigen::Vector2d to_eigen(const cv::Point2f& p) { return {p.x, p.y}; }

}  // namespace

void KeyframeProcessor::start_segment() {
  if (!segment_keyframes_.empty()) {
    previous_segment_ = segment_;
    previous_segment_keyframes_ = std::move(segment_keyframes_);
  }
  segment_ = ++last_segment_;
  segment_keyframes_.clear();
}

KeyframeResult KeyframeProcessor::resume_segment(KeyframeJob job, PointFeatures features) {
  KeyframeResult result;
  result.frame_index = job.frame_index;
  if (!can_resume()) return result;
  const auto T = relocalise(job, features);
  if (!T) return result;
  stats_.add_count("relocalisations");
  segment_ = previous_segment_;
  segment_keyframes_ = std::move(previous_segment_keyframes_);
  previous_segment_keyframes_.clear();
  job.first = false;
  job.tracks.clear();
  job.T_world_cam = *T;
  job.reason = KeyframeReason::kRelocalisation;
  DetectedKeyframe detected;
  detected.features = std::move(features);
  // A keyframe that is not a segment's first is always added: the segment has resumed.
  result = process(job, std::move(detected));
  result.relocalised = true;
  return result;
}

bool KeyframeProcessor::relocalise_in_segment(const KeyframeJob& job, DetectedKeyframe& detected) {
  detected.relocalised_T_world_cam = relocalise(job, detected.features, segment_keyframes_);
  return detected.relocalised_T_world_cam.has_value();
}

std::optional<geometry::Pose> KeyframeProcessor::relocalise(const KeyframeJob& job, const PointFeatures& features,
                                                            const std::vector<Id>& keyframes) {
  const int min_inliers = config_.pose.relocalise_min_inliers;
  if (min_inliers <= 0 || keyframes.empty() || features.size() == 0) return std::nullopt;
  ScopedTimer t(stats_, "kf_relocalise");
  // Each of the last keyframes before the loss holds only the points it saw linked; pooled, they
  // hold more of the map around the loss. A feature and a point each count once (newest first).
  const size_t count =
      std::min(keyframes.size(), static_cast<size_t>(config_.pose.relocalise_keyframes));
  std::vector<Keyframe> recent;
  map_.read([&](const MapData& m) {
    for (auto id = keyframes.rbegin(); id != keyframes.rbegin() + static_cast<std::ptrdiff_t>(count); ++id)
      if (auto it = m.keyframes.find(*id); it != m.keyframes.end()) recent.push_back(it->second);
  });
  std::vector<Eigen::Vector3d> pts;
  std::vector<Eigen::Vector2d> px;
  std::set<Id> used_points;
  std::vector<char> used_features(features.size(), 0);
  for (const Keyframe& kf : recent) {
    const std::vector<PointMatch> matches = matcher_->match(kf.features, features, job.left.size());
    map_.read([&](const MapData& m) {
      for (const auto& mt : matches) {
        const Id pid = kf.point_ids[mt.a];
        if (pid == kNoId || used_features[mt.b] || used_points.count(pid)) continue;
        auto it = m.points.find(pid);
        if (it == m.points.end()) continue;
        pts.push_back(it->second.position);
        px.push_back(to_eigen(features.points[mt.b]));
        used_points.insert(pid);
        used_features[mt.b] = 1;
      }
    });
  }
  if (static_cast<int>(pts.size()) < min_inliers) {
    spdlog::debug("frame {}: no relocalisation, {} matches with map points of the last {} keyframes", job.frame_index,
                  pts.size(), recent.size());
    return std::nullopt;
  }
  const PoseEstimate e = estimate_pose(camera_, pts, px, {}, std::nullopt, config_.geometry, config_.backend);
  spdlog::debug("frame {}: relocalisation against the last {} keyframes: {} matches with map points, {} inliers{}",
                job.frame_index, recent.size(), pts.size(), e.ok ? e.num_point_inliers : 0,
                e.ok && e.num_point_inliers >= min_inliers ? "" : " (not used)");
  if (!e.ok || e.num_point_inliers < min_inliers) return std::nullopt;
  return e.T_world_cam;
}

KeyframeResult KeyframeProcessor::initialize_mono(const KeyframeJob& reference, const PointFeatures& ref_features,
                                                  const std::vector<std::optional<Eigen::Vector3d>>& ref_points_world,
                                                  KeyframeJob second, const std::vector<cv::Point2f>& second_px) {
  second.tracks.clear();
  std::vector<lines::LineSegment> ref_lines;
  cv::Mat ref_line_descriptors;
  if (line_mapper_) {
    ScopedTimer t(stats_, "kf_lines");
    ref_lines = line_mapper_->detect(reference.left);
    if (config_.lines.associator.use_descriptors && !ref_lines.empty())
      ref_line_descriptors = lines::compute_lbd_descriptors(reference.left, ref_lines);
  }
  Id kid = kNoId;
  map_.write([&](MapData& m) {
    Keyframe kf;
    kf.frame_index = reference.frame_index;
    kf.timestamp = reference.timestamp;
    kf.T_world_cam = reference.T_world_cam;
    kf.reason = KeyframeReason::kInitialization;
    kf.segment = segment_;
    kf.features = ref_features;
    for (const auto& l : ref_lines) kf.lines.push_back(to_segment2d(l));
    kf.line_descriptors = ref_line_descriptors;
    kid = m.add_keyframe(std::move(kf));
    for (size_t i = 0; i < ref_features.size(); ++i) {
      if (i >= second_px.size() || std::isnan(second_px[i].x)) continue;
      TrackedPoint tp;
      tp.px = second_px[i];
      tp.origin = {kid, static_cast<int>(i)};
      tp.last = tp.origin;
      if (i < ref_points_world.size() && ref_points_world[i]) {
        tp.point = m.add_point(*ref_points_world[i]);
        m.observe_point(tp.point, kid, static_cast<int>(i));
      }
      second.tracks.push_back(tp);
    }
  });
  segment_keyframes_.push_back(kid);
  remember_image(kid, reference);
  stats_.add_count("keyframes");
  stats_.add_count("keyframes." + to_string(KeyframeReason::kInitialization));
  second.reason = KeyframeReason::kInitialization;
  return process(second);
}

}  // namespace pllvo::vo
