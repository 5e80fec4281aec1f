// Odometry: keyframe results coming back from the worker, merged into the tracks that moved on
// meanwhile (brought up to date through the buffered pyramids, inconsistent tracks dropped).
#include "pllvo/vo/odometry.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>

#include <opencv2/imgproc.hpp>
#include <spdlog/spdlog.h>

#include "pllvo/common/error.h"
#include "pllvo/common/statistics.h"
#include "pllvo/features/lines/cross_constraint.h"
#include "pllvo/nn/runtime.h"
#include "pllvo/vo/odometry_detail.h"

namespace pllvo::vo {

using namespace odometry_detail;

namespace {

/// Index of tracks by identity: map landmark id, else the first keyframe observation.
template <typename Track, typename IdOf>
std::map<std::pair<Id, int>, size_t> index_by_identity(const std::vector<Track>& tracks, IdOf id_of) {
  std::map<std::pair<Id, int>, size_t> index;
  for (size_t i = 0; i < tracks.size(); ++i) {
    const Id id = id_of(tracks[i]);
    if (id != kNoId)
      index[{id, -1}] = i;
    else if (tracks[i].origin.keyframe != kNoId)
      index[{tracks[i].origin.keyframe, tracks[i].origin.index}] = i;
  }
  return index;
}

template <typename Track, typename IdOf>
std::optional<size_t> find_identity(const std::map<std::pair<Id, int>, size_t>& index, const Track& t, IdOf id_of) {
  const Id id = id_of(t);
  if (id != kNoId) {
    auto it = index.find({id, -1});
    if (it != index.end()) return it->second;
  }
  // A candidate that became a landmark on this keyframe is still known by its origin.
  auto it = index.find({t.origin.keyframe, t.origin.index});
  if (t.origin.keyframe != kNoId && it != index.end()) return it->second;
  return std::nullopt;
}

}  // namespace

void Odometry::PyramidBuffer::push(size_t frame_index, const ImagePyramid& pyramid, size_t capacity) {
  std::lock_guard<std::mutex> lock(mutex_);
  frames_.emplace_back(frame_index, pyramid);
  while (frames_.size() > capacity) frames_.pop_front();
}

std::vector<std::pair<size_t, ImagePyramid>> Odometry::PyramidBuffer::from(size_t first) const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<std::pair<size_t, ImagePyramid>> out;
  for (const auto& f : frames_)
    if (f.first >= first) out.push_back(f);
  return out;
}

void Odometry::PyramidBuffer::drop_before(size_t frame_index) {
  std::lock_guard<std::mutex> lock(mutex_);
  while (!frames_.empty() && frames_.front().first < frame_index) frames_.pop_front();
}

void Odometry::PyramidBuffer::clear() {
  std::lock_guard<std::mutex> lock(mutex_);
  frames_.clear();
}

void Odometry::follow(const std::vector<std::pair<size_t, ImagePyramid>>& frames, std::vector<TrackedPoint>& points,
                      std::vector<TrackedLine>& lines) const {
  // follow() also runs on the worker: re-detection there needs its own detector.
  std::optional<lines::LineDetector> detector;
  if (use_lines_ && redetect_lines_ && !lines.empty()) detector.emplace(config_.lines.detector);
  for (size_t k = 1; k < frames.size(); ++k) {
    const ImagePyramid& from = frames[k - 1].second;
    const ImagePyramid& to = frames[k].second;
    if (!points.empty()) {
      std::vector<cv::Point2f> pts;
      for (const auto& p : points) pts.push_back(p.px);
      const TrackResult tr = tracker_.track_with_contrast_fallback(from, to, pts);
      std::vector<TrackedPoint> next;
      for (size_t i = 0; i < points.size(); ++i)
        if (tr.ok[i]) next.push_back({tr.points[i], points[i].point, points[i].origin, points[i].last});
      points = std::move(next);
    }
    std::vector<lines::LineSegment> detections;
    if (detector && !lines.empty()) detections = detector->detect(to.image);
    if (use_lines_) lines = track_lines(from, to, lines, false, nullptr, detector ? &detections : nullptr);
  }
}

std::vector<std::pair<size_t, ImagePyramid>> Odometry::buffered_since(size_t first) const {
  std::vector<std::pair<size_t, ImagePyramid>> frames;
  for (auto& f : pyramid_buffer_.from(first))
    if (f.first <= previous_index_) frames.push_back(std::move(f));
  if (frames.empty() || frames.front().first != first) return {};
  return frames;
}

std::vector<std::pair<size_t, ImagePyramid>> Odometry::frames_from(size_t frame_index,
                                                                   const ImagePyramid& pyramid) const {
  std::vector<std::pair<size_t, ImagePyramid>> frames = {{frame_index, pyramid}};
  for (auto& f : pyramid_buffer_.from(frame_index + 1)) frames.push_back(std::move(f));
  return frames;
}

size_t Odometry::follow_to_newest(const KeyframeJob& job, const FollowStep& step) const {
  std::vector<std::pair<size_t, ImagePyramid>> frames = frames_from(job.frame_index, job.left_pyramid);
  step(frames);
  // A live tracker kept taking frames while the worker followed: what the worker follows now the
  // tracker need not follow when it takes the result, on the frame a camera waits behind.
  for (int round = 0; round < config_.run.worker_catch_up_rounds; ++round) {
    std::vector<std::pair<size_t, ImagePyramid>> more = frames_from(frames.back().first, frames.back().second);
    if (more.size() < 2) break;
    step(more);
    frames = std::move(more);
  }
  return frames.back().first;
}

void Odometry::prepare_result(const KeyframeJob& job, KeyframeResult& result) const {
  auto point_id = [](const TrackedPoint& p) { return p.point; };
  auto line_id = [](const TrackedLine& l) { return l.line; };
  const auto point_index = index_by_identity(job.tracks, point_id);
  const auto line_index = index_by_identity(job.lines, line_id);
  for (const auto& r : result.tracks)
    if (!find_identity(point_index, r, point_id)) result.new_tracks.push_back(r);
  for (const auto& r : result.lines)
    if (!find_identity(line_index, r, line_id)) result.new_lines.push_back(r);
  result.followed_frame = follow_to_newest(job, [&](const auto& frames) {
    follow(frames, result.new_tracks, result.new_lines);
  });
}

void Odometry::apply_keyframe_results() {
  std::deque<KeyframeResult> ready;
  {
    std::lock_guard<std::mutex> lock(results_mutex_);
    ready.swap(results_);
  }
  for (auto& result : ready) {
    pending_keyframe_frames_.erase(result.frame_index);
    if (const auto it = keyframe_requested_at_.find(result.frame_index); it != keyframe_requested_at_.end()) {
      stats_.add_sample("keyframe_return_ms", std::chrono::duration<double, std::milli>(
                                                  std::chrono::steady_clock::now() - it->second).count());
      stats_.add_sample("keyframe_return_frames", static_cast<double>(previous_index_ - result.frame_index));
      keyframe_requested_at_.erase(it);
    }
    if (!result.ok || state_ != TrackingState::kTracking) continue;
    if (metric()) stereo_offset_px_ = result.stereo_offset_px;
    ScopedTimer t(stats_, "catch_up");

    // Points and lines the tracker already follows keep their current position and take the
    // keyframe's identity; the new ones come positioned by the worker and are followed over
    // the last few frames.
    auto point_id = [](const TrackedPoint& p) { return p.point; };
    auto line_id = [](const TrackedLine& l) { return l.line; };
    const auto point_index = index_by_identity(tracks_, point_id);
    const auto line_index = index_by_identity(line_tracks_, line_id);
    std::vector<TrackedPoint> merged;
    std::vector<char> point_taken(tracks_.size(), 0);
    for (const auto& r : result.tracks) {
      const auto i = find_identity(point_index, r, point_id);
      if (!i || point_taken[*i]) continue;
      point_taken[*i] = 1;
      merged.push_back({tracks_[*i].px, r.point, r.origin, r.last,
                        r.point == kNoId ? tracks_[*i].provisional : std::nullopt});
    }
    std::vector<TrackedLine> merged_lines;
    std::vector<char> line_taken(line_tracks_.size(), 0);
    for (const auto& r : result.lines) {
      const auto i = find_identity(line_index, r, line_id);
      if (!i || line_taken[*i]) continue;
      line_taken[*i] = 1;
      TrackedLine l = r;
      l.segment = line_tracks_[*i].segment;
      merged_lines.push_back(l);
    }
    std::vector<TrackedPoint> new_points = result.new_tracks;
    std::vector<TrackedLine> new_lines = result.new_lines;
    if (result.followed_frame < previous_index_) {
      const auto frames = buffered_since(result.followed_frame);
      if (frames.empty()) {
        new_points.clear();  // its pyramid is gone: cannot be brought up to date
        new_lines.clear();
      } else {
        follow(frames, new_points, new_lines);
      }
    }
    merged.insert(merged.end(), new_points.begin(), new_points.end());
    merged_lines.insert(merged_lines.end(), new_lines.begin(), new_lines.end());
    // Current tracks of map points the keyframe did not keep still help the pose.
    for (size_t i = 0; i < tracks_.size(); ++i)
      if (!point_taken[i] && tracks_[i].point != kNoId) merged.push_back(tracks_[i]);
    for (size_t i = 0; i < line_tracks_.size(); ++i)
      if (!line_taken[i] && line_tracks_[i].line != kNoId) merged_lines.push_back(line_tracks_[i]);
    drop_inconsistent_tracks(merged, result);
    drop_inconsistent_lines(merged_lines);
    tracks_ = std::move(merged);
    policy_.set_reference_points(count_mapped(tracks_));
    if (use_lines_) {
      spdlog::debug("keyframe of frame {}: {} lines followed, {} of them mapped", result.frame_index,
                    merged_lines.size(), count_mapped_lines(merged_lines));
      line_tracks_ = std::move(merged_lines);
      // The lines the tracker follows from now on, not the keyframe's own list (which holds
      // lines the tracker lost meanwhile and lacks map lines it keeps): against the latter the
      // overlap-angle trigger fired on the very next frame.
      set_reference_lines(line_tracks_);
    }
  }
  if (pending_keyframe_frames_.empty())
    pyramid_buffer_.clear();
  else
    pyramid_buffer_.drop_before(*pending_keyframe_frames_.begin());
}

void Odometry::drop_inconsistent_tracks(std::vector<TrackedPoint>& tracks, const KeyframeResult& result) {
  // The tracker's latest pose comes from the points it already follows; a keyframe that
  // comes back late brings points triangulated at its own pose and followed over the frames
  // since. Those that do not project near where they are tracked now (a drifted follow, a
  // point triangulated from a wrong match) would split the next PnP into two consensus sets
  // and make the pose jump: they are dropped.
  const double gate = config_.pose.merge_gate_px;
  // A map held for this keyframe (pose.hold_map_for_keyframe_s) has no pose of the frame its
  // tracks are in: the next pose's RANSAC sorts them.
  if (gate <= 0 || holding_map()) return;
  std::vector<int> slot(tracks.size(), -1);  // index in points / pixels, -1: no map point
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector2d> pixels;
  map_.read([&](const MapData& m) {
    for (size_t i = 0; i < tracks.size(); ++i) {
      auto it = tracks[i].point == kNoId ? m.points.end() : m.points.find(tracks[i].point);
      if (it == m.points.end()) continue;
      slot[i] = static_cast<int>(points.size());
      points.push_back(it->second.position);
      pixels.push_back(to_eigen(tracks[i].px));
    }
  });
  if (config_.pose.follow_keyframe_adjustment) {
    if (const auto moved = follow_keyframe_adjustment(camera_, points, pixels, T_world_work_, result.T_world_cam,
                                                      result.T_world_cam_adjusted, gate)) {
      spdlog::debug("keyframe of frame {}: its adjustment moves the current pose", result.frame_index);
      T_world_work_ = *moved;
      stats_.add_count("poses_moved_by_adjustment");
    }
  }
  if (config_.pose.merge_pose_by_pnp) {
    // The tracker's pose may rest on the few points a fast turn left it, the keyframe's on the
    // many it was followed from.
    if (const auto T = pose_of_merged_tracks(camera_, points, pixels, T_world_work_, gate, config_.geometry.pnp)) {
      spdlog::debug("keyframe of frame {}: the current pose by PnP on the merged tracks", result.frame_index);
      T_world_work_ = *T;
      stats_.add_count("poses_from_merged_tracks");
    }
  }
  const std::vector<double> errors = reprojection_errors_px(camera_, points, pixels, T_world_work_);
  std::vector<TrackedPoint> kept;
  kept.reserve(tracks.size());
  for (size_t i = 0; i < tracks.size(); ++i)
    if (slot[i] < 0 || errors[slot[i]] <= gate) kept.push_back(tracks[i]);
  spdlog::debug("keyframe of frame {} merged at frame {}: {} of {} map points within {} px (median {:.2f} px)",
                result.frame_index, previous_index_, kept.size(), tracks.size(), gate, median(errors));
  stats_.add_count("merge_dropped_points", static_cast<long long>(tracks.size() - kept.size()));
  tracks = std::move(kept);
}

void Odometry::drop_inconsistent_lines(std::vector<TrackedLine>& lines) const {
  // As for points: a late keyframe's lines were followed without a pose prediction.
  const double gate = config_.pose.merge_gate_px;
  if (gate <= 0) return;
  const geometry::Pose T_work_world = T_world_work_.inverse();
  std::vector<TrackedLine> kept;
  kept.reserve(lines.size());
  size_t dropped = 0;
  map_.read([&](const MapData& m) {
    for (auto& l : lines) {
      auto it = l.line == kNoId ? m.lines.end() : m.lines.find(l.line);
      if (it == m.lines.end()) {
        kept.push_back(l);
        continue;
      }
      Eigen::Vector2d a, b;
      const Eigen::Vector2d d = l.segment.end - l.segment.start;
      bool ok = d.norm() > 1 && camera_.project(T_work_world * it->second.p, a) &&
                camera_.project(T_work_world * it->second.q, b);
      if (ok) {
        const Eigen::Vector2d n(-d.y() / d.norm(), d.x() / d.norm());
        ok = std::abs(n.dot(a - l.segment.start)) <= gate && std::abs(n.dot(b - l.segment.start)) <= gate;
      }
      if (ok)
        kept.push_back(l);
      else
        ++dropped;
    }
  });
  stats_.add_count("merge_dropped_lines", static_cast<long long>(dropped));
  lines = std::move(kept);
}

}  // namespace pllvo::vo
