// Odometry: starting a map (stereo on one frame, monocular from two views or resumed in the map
// before a loss) and what a loss resets.
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

bool Odometry::initialize(const io::Frame& frame, const cv::Mat& left, const cv::Mat& right,
                          const ImagePyramid& pyramid, std::optional<DetectedKeyframe> detected, bool* relocalised) {
  ScopedTimer t(stats_, "init");
  if (frame_brightness_ < config_.init.min_brightness) {
    if (!two_view_start_) mono_.reset();  // a two-view start on the worker still needs its reference
    return false;
  }
  return metric() ? initialize_stereo(frame, left, right, pyramid, std::move(detected), relocalised)
                             : initialize_mono(frame, left, pyramid);
}

bool Odometry::initialize_stereo(const io::Frame& frame, const cv::Mat& left, const cv::Mat& right,
                                 const ImagePyramid& pyramid, std::optional<DetectedKeyframe> detected,
                                 bool* relocalised) {
  // Without a detection, the start runs on the worker: a live tracker keeps taking frames
  // meanwhile, and process() applies the outcome on the frame it comes back at.
  if (!detected && start_in_flight_) return false;
  KeyframeJob job = make_keyframe_job(frame, left, right, pyramid, KeyframeReason::kInitialization);
  job.first = true;
  job.T_world_cam = restart_pose(frame.index, frame.timestamp);
  if (!detected) {
    submit_metric_start(job);
    return apply_start_outcome(frame.index, relocalised);
  }
  const KeyframeResult result = processor_.process(job, std::move(*detected));
  if (!result.ok) return false;
  T_world_work_ = result.T_world_cam;
  start_tracking(result, frame.timestamp);
  if (relocalised) *relocalised = result.relocalised;
  spdlog::info("{} initialisation at frame {}: {} points{}", stereo() ? "stereo" : "RGB-D", frame.index,
               result.tracks.size(),
               result.relocalised ? ", relocalised in the map before the loss" : "");
  return true;
}

std::vector<Eigen::Vector3d> Odometry::start_directions(const cv::Mat& image, size_t frame_index) {
  if (!use_directions_ || config_.geometry.two_view.vanishing_sigma_deg <= 0) return {};
  ScopedTimer t(stats_, "direction_lines");
  return image_directions(direction_segments(image, frame_index), camera_.focal(), config_.directions);
}

bool Odometry::may_resume(const io::Frame& frame) const {
  const double max_gap = config_.pose.mono_resume_max_s;
  return max_gap > 0 && processor_.can_resume() && frame.timestamp - last_tracked_time_ <= max_gap;
}

bool Odometry::initialize_mono(const io::Frame& frame, const cv::Mat& left, const ImagePyramid& pyramid) {
  // A detection (a resume try, or a new reference's features) runs on the worker; the two-view
  // start below needs only KLT and goes on while it runs.
  if (!start_in_flight_ && (!mono_ || (may_resume(frame) && !two_view_waiting_))) {
    const bool had_reference = mono_ != nullptr;
    submit_start_detection(frame, left, pyramid, may_resume(frame));
    if (apply_start_outcome(frame.index)) return true;
    if (!had_reference) return false;
  }
  if (!mono_ || two_view_start_) return false;
  auto& ref = *mono_;
  ++ref.frames;
  std::vector<int> which;
  std::vector<cv::Point2f> from;
  for (int i = 0; i < static_cast<int>(ref.current.size()); ++i)
    if (ref.alive[i]) which.push_back(i), from.push_back(ref.current[i]);
  const TrackResult tr = tracker_.track_with_contrast_fallback(previous_pyramid_, pyramid, from);
  std::vector<Eigen::Vector2d> px0, px1;
  std::vector<double> flow;
  for (size_t k = 0; k < which.size(); ++k) {
    const int i = which[k];
    if (!tr.ok[k]) {
      ref.alive[i] = 0;
      continue;
    }
    ref.current[i] = tr.points[k];
    px0.push_back(to_eigen(ref.features.points[i]));
    px1.push_back(to_eigen(tr.points[k]));
    flow.push_back((px1.back() - px0.back()).norm());
  }
  ref.history.emplace_back(frame.index, std::vector<cv::Point2f>(ref.features.size(), cv::Point2f(NAN, NAN)));
  for (size_t i = 0; i < ref.current.size(); ++i)
    if (ref.alive[i]) ref.history.back().second[i] = ref.current[i];
  const int alive = static_cast<int>(px0.size());
  const double median_flow = median(flow);
  spdlog::debug("frame {}: monocular start from frame {}: {} of {} points followed, median flow {:.1f} px (needs {} and {:.0f})",
                frame.index, ref.frame_index, alive, ref.features.size(), median_flow, config_.init.min_points,
                config_.init.mono_min_flow_px);
  if (alive < config_.init.min_points || ref.frames > static_cast<size_t>(config_.init.max_frames)) {
    // A new reference on this frame: on the detection made for it already, else on a new one.
    mono_.reset();
    if (spare_detection_ && spare_detection_->frame_index == frame.index) {
      StartOutcome spare = std::move(*spare_detection_);
      open_reference(spare, false);
    } else if (!start_in_flight_) {
      submit_start_detection(frame, left, pyramid, false);
      apply_start_outcome(frame.index);
    }
    return false;
  }
  if (median_flow < config_.init.mono_min_flow_px) return false;
  // One start step at a time: a resume try still running is waited for on later frames.
  two_view_waiting_ = start_in_flight_;
  if (start_in_flight_) return false;

  const geometry::ViewDirections directions{ref.directions, start_directions(left, frame.index)};
  const TwoViewInit two_view = initialize_two_view(camera_, px0, px1, config_.geometry.two_view, &directions);
  if (!two_view.ok) {
    // The direction is measured only for a motion that passed the earlier checks.
    const std::string direction =
        std::isfinite(two_view.direction_sigma_deg)
            ? fmt::format(", direction sigma {:.1f} deg at {:.2f} px", two_view.direction_sigma_deg,
                          two_view.residual_rms_px)
            : std::string();
    spdlog::debug("frame {}: two-view initialisation failed ({}: {}; {} of {} matches fit, {} triangulated, median "
                  "parallax {:.2f} deg{})",
                  frame.index, two_view.model, two_view.failure, two_view.num_inliers, px0.size(),
                  two_view.num_triangulated, two_view.median_parallax_deg, direction);
    return false;
  }

  // World = the reference camera's frame at the current segment start pose.
  MonoStart start;
  start.T_world_ref = restart_pose(ref.frame_index, ref.timestamp);
  start.T_world_cur = start.T_world_ref * two_view.T_cam1_cam0.inverse();
  start.points.resize(ref.features.size());
  std::vector<cv::Point2f> second_px(ref.features.size(), cv::Point2f(NAN, NAN));
  KeyframeJob second = make_keyframe_job(frame, left, cv::Mat(), pyramid, KeyframeReason::kInitialization);
  second.T_world_cam = start.T_world_cur;
  int made = 0;
  for (size_t k = 0, j = 0; k < which.size(); ++k) {
    const int i = which[k];
    if (!tr.ok[k]) continue;
    second_px[i] = tr.points[k];
    if (two_view.points_cam0[j]) start.points[i] = start.T_world_ref * *two_view.points_cam0[j], ++made;
    ++j;
  }
  if (made < config_.init.min_points) {
    spdlog::debug("frame {}: two-view initialisation triangulated only {} points", frame.index, made);
    return false;
  }
  KeyframeJob reference;
  reference.frame_index = ref.frame_index;
  reference.timestamp = ref.timestamp;
  reference.left = ref.image;
  reference.T_world_cam = start.T_world_ref;
  const std::string held = config_.geometry.two_view.vanishing_sigma_deg > 0
                               ? fmt::format(", rotation held by {} of {}/{} directions", two_view.vanishing_pairs,
                                             directions.cam0.size(), directions.cam1.size())
                               : std::string();
  start.summary = fmt::format("monocular initialisation ({}) between frames {} and {}: {} points, median parallax "
                              "{:.2f} deg, direction sigma {:.1f} deg{}",
                              two_view.model, reference.frame_index, frame.index, made, two_view.median_parallax_deg,
                              two_view.direction_sigma_deg, held);
  const std::vector<std::optional<Eigen::Vector3d>> points = start.points;
  two_view_start_ = std::move(start);
  submit_two_view_start(reference, ref.features, points, second, second_px);
  return apply_start_outcome(frame.index);
}

FrameRecord* Odometry::record_of(size_t frame_index) {
  // Records of recent frames are the last ones.
  for (auto it = records_.rbegin(); it != records_.rend(); ++it)
    if (it->index == frame_index) return &*it;
  return nullptr;
}

void Odometry::localize_init_frames(const MonoReference& ref,
                                    const std::vector<std::optional<Eigen::Vector3d>>& points,
                                    const geometry::Pose& T_world_ref) {
  // The reference frame itself is the first keyframe.
  if (FrameRecord* r = record_of(ref.frame_index)) {
    r->tracked = true;
    r->T_world_cam = to_output(T_world_ref);
    r->tracked_points = static_cast<int>(std::count_if(points.begin(), points.end(), [](const auto& p) { return p.has_value(); }));
  }
  for (const auto& [frame_index, px] : ref.history) {
    FrameRecord* r = record_of(frame_index);
    if (!r) continue;  // the current frame
    std::vector<Eigen::Vector3d> pts;
    std::vector<Eigen::Vector2d> obs;
    for (size_t i = 0; i < px.size(); ++i)
      if (points[i] && !std::isnan(px[i].x)) pts.push_back(*points[i]), obs.push_back(to_eigen(px[i]));
    const PoseEstimate e = estimate_pose_pnp(camera_, pts, obs, config_.geometry.pnp);
    if (!e.ok) continue;
    r->tracked = true;
    r->T_world_cam = to_output(e.T_world_cam);
    r->tracked_points = e.num_point_inliers;
  }
}

void Odometry::start_tracking(const KeyframeResult& result, double timestamp) {
  state_ = TrackingState::kTracking;
  tracks_ = result.tracks;
  line_tracks_ = result.lines;
  corners_.clear();
  set_reference_lines(line_tracks_);
  has_velocity_ = false;
  velocity_ = geometry::Pose::Identity();
  lost_frames_ = 0;
  policy_.start_keyframe(timestamp, count_mapped(tracks_));
}

// ---------------------------------------------------------------- tracking

void Odometry::handle_lost(double timestamp) {
  ++lost_frames_;
  stats_.add_count("lost_frames_while_tracking");
  if (lost_frames_ < config_.pose.lost_frames_before_reset) return;
  // Live, the keyframe in flight would bring the points this map lacks (and reset() waits for
  // it only to throw it away); offline the tracker waited for it before getting here. A metric
  // map restarts on one frame: held, it tracked fewer frames live (docs/vo.md).
  const double hold = config_.pose.hold_map_for_keyframe_s;
  if (!config_.run.wait_when_starving && !metric() && hold > 0 && !pending_keyframe_frames_.empty() &&
      timestamp - last_tracked_time_ <= hold) {
    stats_.add_count("lost_frames_held_for_keyframe");
    return;
  }
  reset();
}

void Odometry::reset() {
  spdlog::warn("tracking lost after frame {}: re-initialising", previous_index_);
  worker_.wait_idle();
  worker_.rethrow_if_failed();
  {
    std::lock_guard<std::mutex> lock(results_mutex_);
    results_.clear();
  }
  pending_keyframe_frames_.clear();
  keyframe_requested_at_.clear();
  pyramid_buffer_.clear();
  tracks_.clear();
  line_tracks_.clear();
  corners_.clear();
  frame_directions_.clear();
  reference_angles_ = {};
  mono_.reset();
  two_view_start_.reset();
  start_in_flight_ = false;
  start_outcome_.reset();
  spare_detection_.reset();
  two_view_waiting_ = false;
  state_ = TrackingState::kUninitialized;
  gap_step_world_.reset();
  if (recent_positions_.size() >= 2) {
    const auto& [first, p_first] = recent_positions_.front();
    const auto& [last, p_last] = recent_positions_.back();
    gap_step_world_ = (p_last - p_first) / static_cast<double>(last - first);
  }
  recent_positions_.clear();
  has_velocity_ = false;
  lost_frames_ = 0;
  ++resets_;
  stats_.add_count("resets");
  processor_.start_segment();
  policy_ = KeyframePolicy(config_.keyframes);
  // The new segment starts at the last tracked pose, so the trajectory stays continuous
  // (up to the unknown scale of a new monocular map).
}

geometry::Pose Odometry::restart_pose(size_t frame_index, double timestamp) const {
  const double max_gap = config_.pose.extrapolate_gap_max_s;
  if (!gap_step_world_ || max_gap <= 0 || frame_index <= last_tracked_index_ ||
      timestamp - last_tracked_time_ > max_gap)
    return T_world_work_;
  // Only the position is carried on: over a few frames the rotation rate of a swinging camera
  // changes more than its speed does (docs/vo.md), and the last orientation was the
  // better guess on the measured gaps.
  geometry::Pose start = T_world_work_;
  start.translation() += static_cast<double>(frame_index - last_tracked_index_) * *gap_step_world_;
  return start;
}

void Odometry::remember_position(size_t frame_index, const Eigen::Vector3d& position) {
  // Consecutive tracked frames only: a step across lost frames is not one frame's motion.
  if (!recent_positions_.empty() && recent_positions_.back().first + 1 != frame_index) recent_positions_.clear();
  recent_positions_.emplace_back(frame_index, position);
  while (recent_positions_.size() > static_cast<size_t>(config_.pose.extrapolate_velocity_frames) + 1)
    recent_positions_.pop_front();
}

// ---------------------------------------------------------------- results

}  // namespace pllvo::vo
