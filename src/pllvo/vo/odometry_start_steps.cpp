// Odometry: a start's network steps on the keyframe worker (a stereo or RGB-D map's first
// keyframe; monocular: a detection that tries to resume the map before a loss or opens a
// reference, the two keyframes of a two-view start) and how their outcome reaches the tracker,
// which kept taking frames meanwhile.
#include <spdlog/spdlog.h>

#include "pllvo/common/statistics.h"
#include "pllvo/vo/odometry.h"
#include "pllvo/vo/odometry_detail.h"

namespace pllvo::vo {

using namespace odometry_detail;

namespace {

/// The pose at which the map points among `points` are where they are tracked.
std::optional<geometry::Pose> pose_of_tracks(const Pinhole& camera, const Map& map,
                                             const std::vector<TrackedPoint>& points,
                                             const geometry::PnpConfig& config) {
  std::vector<Eigen::Vector3d> world;
  std::vector<Eigen::Vector2d> pixels;
  map.read([&](const MapData& m) {
    for (const auto& p : points) {
      auto it = p.point == kNoId ? m.points.end() : m.points.find(p.point);
      if (it == m.points.end()) continue;
      world.push_back(it->second.position);
      pixels.push_back(to_eigen(p.px));
    }
  });
  const PoseEstimate e = estimate_pose_pnp(camera, world, pixels, config);
  if (!e.ok) return std::nullopt;
  return e.T_world_cam;
}

/// An outcome of a step on `job`'s frame.
StartOutcome outcome_at(const KeyframeJob& job) {
  StartOutcome outcome;
  outcome.frame_index = job.frame_index;
  outcome.timestamp = job.timestamp;
  outcome.image = job.left;
  return outcome;
}

}  // namespace

void Odometry::submit_start(size_t frame_index, std::function<StartOutcome()> step) {
  start_in_flight_ = true;
  pending_keyframe_frames_.insert(frame_index);  // keeps the pyramids that the outcome catches up through
  stats_.add_count("start_steps");
  worker_.submit([this, step = std::move(step)] {
    StartOutcome outcome = step();
    std::lock_guard<std::mutex> lock(results_mutex_);
    start_outcome_ = std::move(outcome);
  });
  if (config_.run.wait_when_starving) worker_.wait_idle();
  worker_.rethrow_if_failed();
}

void Odometry::catch_up_on_worker(const KeyframeJob& job, StartOutcome& outcome) const {
  ScopedTimer t(stats_, "kf_catch_up");
  KeyframeResult& result = outcome.result;
  result.new_tracks = result.tracks;
  result.new_lines = result.lines;
  result.followed_frame = follow_to_newest(job, [&](const auto& frames) {
    follow_and_locate(frames, result.new_tracks, result.new_lines, outcome.poses);
  });
}

void Odometry::submit_start_detection(const io::Frame& frame, const cv::Mat& left, const ImagePyramid& pyramid,
                                      bool resume) {
  // The pose comes from the relocalisation itself.
  auto job = std::make_shared<const KeyframeJob>(
      make_keyframe_job(frame, left, cv::Mat(), pyramid, KeyframeReason::kRelocalisation));
  submit_start(frame.index, [this, job, resume] {
    StartOutcome outcome = outcome_at(*job);
    PointFeatures features = processor_.detect(job->left);
    if (resume) {
      outcome.result = processor_.resume_segment(*job, features);
      if (outcome.result.ok) {
        catch_up_on_worker(*job, outcome);
        return outcome;
      }
    }
    std::vector<cv::Point2f> positions = features.points;
    follow_to_newest(*job, [&](const auto& frames) { follow_positions(frames, positions, outcome.followed); });
    outcome.features = std::move(features);
    return outcome;
  });
}

void Odometry::submit_metric_start(const KeyframeJob& job) {
  auto first = std::make_shared<const KeyframeJob>(job);
  submit_start(job.frame_index, [this, first] {
    StartOutcome outcome = outcome_at(*first);
    outcome.result = processor_.process(*first);
    if (outcome.result.ok) catch_up_on_worker(*first, outcome);
    return outcome;
  });
}

void Odometry::submit_two_view_start(const KeyframeJob& reference, const PointFeatures& features,
                                     const std::vector<std::optional<Eigen::Vector3d>>& points,
                                     const KeyframeJob& second, const std::vector<cv::Point2f>& second_px) {
  auto ref = std::make_shared<const KeyframeJob>(reference);
  auto ref_features = std::make_shared<const PointFeatures>(features);
  auto ref_points = std::make_shared<const std::vector<std::optional<Eigen::Vector3d>>>(points);
  auto next = std::make_shared<const KeyframeJob>(second);
  auto next_px = std::make_shared<const std::vector<cv::Point2f>>(second_px);
  submit_start(second.frame_index, [this, ref, ref_features, ref_points, next, next_px] {
    StartOutcome outcome = outcome_at(*next);
    outcome.result = processor_.initialize_mono(*ref, *ref_features, *ref_points, *next, *next_px);
    if (outcome.result.ok) catch_up_on_worker(*next, outcome);
    return outcome;
  });
}

bool Odometry::apply_start_outcome(size_t current, bool* relocalised) {
  std::optional<StartOutcome> outcome;
  {
    std::lock_guard<std::mutex> lock(results_mutex_);
    outcome.swap(start_outcome_);
  }
  if (!outcome) return false;
  start_in_flight_ = false;
  pending_keyframe_frames_.erase(outcome->frame_index);
  const bool late = outcome->frame_index != current;
  if (late) stats_.add_count("start_steps_applied_late");
  std::optional<MonoStart> start;
  start.swap(two_view_start_);
  if (!outcome->result.ok) {
    if (metric()) return false;  // the next frame tries again
    if (start) {
      mono_.reset();  // the two-view start's keyframes failed
    } else if (!mono_) {
      open_reference(*outcome, late);
    } else {
      spare_detection_ = std::move(outcome);
    }
    return false;
  }
  const size_t started_points = outcome->result.tracks.size();
  std::vector<TrackedPoint> points = std::move(outcome->result.new_tracks);
  std::vector<TrackedLine> lines = std::move(outcome->result.new_lines);
  geometry::Pose T_world_latest = start ? start->T_world_cur : outcome->result.T_world_cam;
  if (late) {
    const auto frames = buffered_since(outcome->result.followed_frame);
    if (frames.empty()) {
      spdlog::debug("frame {}: the start of frame {} came back too late to follow", current, outcome->frame_index);
      mono_.reset();
      return false;
    }
    follow_and_locate(frames, points, lines, outcome->poses);
  }
  if (late && !start) outcome->poses.emplace(outcome->poses.begin(), outcome->frame_index, outcome->result.T_world_cam);
  for (const auto& [frame_index, T] : outcome->poses) {
    FrameRecord* record = record_of(frame_index);
    if (!record) continue;
    record->tracked = true;
    record->T_world_cam = to_output(T);
    T_world_latest = T;
  }
  if (start && mono_) localize_init_frames(*mono_, start->points, start->T_world_ref);
  mono_.reset();
  spare_detection_.reset();
  T_world_work_ = T_world_latest;
  KeyframeResult tracked;
  tracked.tracks = std::move(points);
  tracked.lines = std::move(lines);
  start_tracking(tracked, outcome->timestamp);
  const std::string when = late ? fmt::format(" (tracking from frame {})", current) : std::string();
  if (relocalised && !late) *relocalised = outcome->result.relocalised;
  if (start)
    spdlog::info("{}{}", start->summary, when);
  else if (metric())
    spdlog::info("{} initialisation at frame {}: {} points{}{}", stereo() ? "stereo" : "RGB-D", outcome->frame_index,
                 started_points, outcome->result.relocalised ? ", relocalised in the map before the loss" : "", when);
  else
    spdlog::info("frame {}: relocalised in the map before the loss ({} points): monocular tracking resumes at its "
                 "scale{}",
                 outcome->frame_index, count_mapped(tracks_), when);
  return !late;
}

void Odometry::follow_and_locate(const std::vector<std::pair<size_t, ImagePyramid>>& frames,
                                 std::vector<TrackedPoint>& points, std::vector<TrackedLine>& lines,
                                 std::vector<std::pair<size_t, geometry::Pose>>& poses) const {
  for (size_t k = 1; k < frames.size(); ++k) {
    follow({frames[k - 1], frames[k]}, points, lines);
    if (const auto T = pose_of_tracks(camera_, map_, points, config_.geometry.pnp))
      poses.emplace_back(frames[k].first, *T);
  }
}

void Odometry::open_reference(StartOutcome& outcome, bool late) {
  spare_detection_.reset();
  if (static_cast<int>(outcome.features.size()) < config_.init.min_points) {
    spdlog::debug("frame {}: no monocular start: {} features (needs {})", outcome.frame_index,
                  outcome.features.size(), config_.init.min_points);
    mono_.reset();
    return;
  }
  std::vector<cv::Point2f> positions =
      outcome.followed.empty() ? outcome.features.points : outcome.followed.back().second;
  if (late) {
    const size_t followed = outcome.followed.empty() ? outcome.frame_index : outcome.followed.back().first;
    const auto frames = buffered_since(followed);
    if (frames.empty()) {
      mono_.reset();
      return;
    }
    follow_positions(frames, positions, outcome.followed);
  }
  mono_ = std::make_unique<MonoReference>();
  mono_->frame_index = outcome.frame_index;
  mono_->timestamp = outcome.timestamp;
  mono_->image = outcome.image;
  mono_->current = positions;
  mono_->alive.resize(positions.size());
  for (size_t i = 0; i < positions.size(); ++i) mono_->alive[i] = std::isnan(positions[i].x) ? 0 : 1;
  mono_->frames = outcome.followed.size();
  mono_->history = std::move(outcome.followed);
  mono_->features = std::move(outcome.features);
  mono_->directions = start_directions(outcome.image, outcome.frame_index);
}

void Odometry::follow_positions(const std::vector<std::pair<size_t, ImagePyramid>>& frames,
                                std::vector<cv::Point2f>& positions,
                                std::vector<std::pair<size_t, std::vector<cv::Point2f>>>& history) const {
  for (size_t k = 1; k < frames.size(); ++k) {
    std::vector<size_t> which;
    std::vector<cv::Point2f> from;
    for (size_t i = 0; i < positions.size(); ++i)
      if (!std::isnan(positions[i].x)) which.push_back(i), from.push_back(positions[i]);
    const TrackResult tr = tracker_.track_with_contrast_fallback(frames[k - 1].second, frames[k].second, from);
    for (size_t j = 0; j < which.size(); ++j)
      positions[which[j]] = tr.ok[j] ? tr.points[j] : cv::Point2f(NAN, NAN);
    history.emplace_back(frames[k].first, positions);
  }
}

}  // namespace pllvo::vo
