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
    mono_.reset();
    return false;
  }
  return metric() ? initialize_stereo(frame, left, right, pyramid, std::move(detected), relocalised)
                             : initialize_mono(frame, left, pyramid);
}

bool Odometry::initialize_stereo(const io::Frame& frame, const cv::Mat& left, const cv::Mat& right,
                                 const ImagePyramid& pyramid, std::optional<DetectedKeyframe> detected,
                                 bool* relocalised) {
  KeyframeJob job = make_keyframe_job(frame, left, right, pyramid, KeyframeReason::kInitialization);
  job.first = true;
  job.T_world_cam = restart_pose(frame.index, frame.timestamp);
  const KeyframeResult result =
      detected ? processor_.process(job, std::move(*detected)) : processor_.process(job);
  if (!result.ok) return false;
  T_world_work_ = result.T_world_cam;
  start_tracking(result, frame.timestamp);
  if (relocalised) *relocalised = result.relocalised;
  spdlog::info("{} initialisation at frame {}: {} points{}", stereo() ? "stereo" : "RGB-D", frame.index,
               result.tracks.size(),
               result.relocalised ? ", relocalised in the map before the loss" : "");
  return true;
}

void Odometry::start_mono_reference(const io::Frame& frame, const cv::Mat& left,
                                    std::optional<PointFeatures> detected) {
  PointFeatures features = detected ? std::move(*detected) : processor_.detect(left);
  if (static_cast<int>(features.size()) < config_.init.min_points) {
    spdlog::debug("frame {}: no monocular start: {} features (needs {})", frame.index, features.size(),
                  config_.init.min_points);
    mono_.reset();
    return;
  }
  mono_ = std::make_unique<MonoReference>();
  mono_->frame_index = frame.index;
  mono_->timestamp = frame.timestamp;
  mono_->image = left;
  mono_->current = features.points;
  mono_->alive.assign(features.size(), 1);
  mono_->features = std::move(features);
  mono_->directions = start_directions(left, frame.index);
}

std::vector<Eigen::Vector3d> Odometry::start_directions(const cv::Mat& image, size_t frame_index) {
  if (!use_directions_ || config_.geometry.two_view.vanishing_sigma_deg <= 0) return {};
  ScopedTimer t(stats_, "direction_lines");
  return image_directions(direction_segments(image, frame_index), camera_.focal(), config_.directions);
}

bool Odometry::resume_mono(const io::Frame& frame, const cv::Mat& left, const ImagePyramid& pyramid,
                           std::optional<PointFeatures>& detected) {
  const double max_gap = config_.pose.mono_resume_max_s;
  if (max_gap <= 0 || !processor_.can_resume() || frame.timestamp - last_tracked_time_ > max_gap) return false;
  detected = processor_.detect(left);
  // The pose comes from the relocalisation itself.
  const KeyframeJob job = make_keyframe_job(frame, left, cv::Mat(), pyramid, KeyframeReason::kRelocalisation);
  const KeyframeResult result = processor_.resume_segment(job, *detected);
  if (!result.ok) return false;
  mono_.reset();
  T_world_work_ = result.T_world_cam;
  start_tracking(result, frame.timestamp);
  spdlog::info("frame {}: relocalised in the map before the loss ({} points): monocular tracking resumes at its scale",
               frame.index, count_mapped(tracks_));
  return true;
}

bool Odometry::initialize_mono(const io::Frame& frame, const cv::Mat& left, const ImagePyramid& pyramid) {
  std::optional<PointFeatures> detected;
  if (resume_mono(frame, left, pyramid, detected)) return true;
  if (!mono_ || previous_pyramid_.empty()) {
    start_mono_reference(frame, left, std::move(detected));
    return false;
  }
  auto& ref = *mono_;
  ++ref.frames;
  std::vector<int> which;
  std::vector<cv::Point2f> from;
  for (int i = 0; i < static_cast<int>(ref.current.size()); ++i)
    if (ref.alive[i]) which.push_back(i), from.push_back(ref.current[i]);
  const TrackResult tr = tracker_.track(previous_pyramid_, pyramid, from);
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
    start_mono_reference(frame, left, std::move(detected));
    return false;
  }
  if (median_flow < config_.init.mono_min_flow_px) return false;

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
  const geometry::Pose T_world_ref = restart_pose(ref.frame_index, ref.timestamp);
  const geometry::Pose T_world_cur = T_world_ref * two_view.T_cam1_cam0.inverse();
  std::vector<std::optional<Eigen::Vector3d>> ref_points(ref.features.size());
  std::vector<cv::Point2f> second_px(ref.features.size(), cv::Point2f(NAN, NAN));
  KeyframeJob second = make_keyframe_job(frame, left, cv::Mat(), pyramid, KeyframeReason::kInitialization);
  second.T_world_cam = T_world_cur;
  int made = 0;
  for (size_t k = 0, j = 0; k < which.size(); ++k) {
    const int i = which[k];
    if (!tr.ok[k]) continue;
    second_px[i] = tr.points[k];
    if (two_view.points_cam0[j]) ref_points[i] = T_world_ref * *two_view.points_cam0[j], ++made;
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
  reference.T_world_cam = T_world_ref;
  const KeyframeResult result = processor_.initialize_mono(reference, ref.features, ref_points, second, second_px);
  if (!result.ok) {
    mono_.reset();
    return false;
  }
  localize_init_frames(ref, ref_points, T_world_ref);
  mono_.reset();
  T_world_work_ = T_world_cur;
  start_tracking(result, frame.timestamp);
  const std::string held = config_.geometry.two_view.vanishing_sigma_deg > 0
                               ? fmt::format(", rotation held by {} of {}/{} directions", two_view.vanishing_pairs,
                                             directions.cam0.size(), directions.cam1.size())
                               : std::string();
  spdlog::info("monocular initialisation ({}) between frames {} and {}: {} points, median parallax {:.2f} deg, "
               "direction sigma {:.1f} deg{}",
               two_view.model, reference.frame_index, frame.index, made, two_view.median_parallax_deg,
               two_view.direction_sigma_deg, held);
  return true;
}

void Odometry::localize_init_frames(const MonoReference& ref,
                                    const std::vector<std::optional<Eigen::Vector3d>>& points,
                                    const geometry::Pose& T_world_ref) {
  // Records of the frames since the reference are the last ones (the current frame's is not
  // in yet); the reference frame itself is the first keyframe.
  auto record_of = [&](size_t frame_index) -> FrameRecord* {
    for (auto it = records_.rbegin(); it != records_.rend(); ++it)
      if (it->index == frame_index) return &*it;
    return nullptr;
  };
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
  set_reference_lines(line_tracks_);
  has_velocity_ = false;
  velocity_ = geometry::Pose::Identity();
  lost_frames_ = 0;
  policy_.start_keyframe(timestamp, count_mapped(tracks_));
}

// ---------------------------------------------------------------- tracking

void Odometry::handle_lost() {
  ++lost_frames_;
  stats_.add_count("lost_frames_while_tracking");
  if (lost_frames_ >= config_.pose.lost_frames_before_reset) reset();
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
  pyramid_buffer_.clear();
  tracks_.clear();
  line_tracks_.clear();
  frame_directions_.clear();
  reference_angles_ = {};
  mono_.reset();
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
