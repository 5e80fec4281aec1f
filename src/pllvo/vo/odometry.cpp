#include "pllvo/vo/odometry.h"

#include <algorithm>
#include <chrono>
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

namespace {

/// Where a keyframe's time goes between its request and its result (`pllvo -v`): queued behind
/// another, detection, waiting for the second stage, matching to BA, following to the newest frame.
struct KeyframeTimeline {
  using Clock = std::chrono::steady_clock;
  Clock::time_point requested = Clock::now(), detection_start, detection_end, process_start, process_end;

  void log(size_t frame_index) const {
    auto ms = [](Clock::time_point a, Clock::time_point b) {
      return std::chrono::duration<double, std::milli>(b - a).count();
    };
    spdlog::debug("keyframe of frame {}: queued {:.0f} ms, detection {:.0f}, to the second stage {:.0f}, "
                  "matching to BA {:.0f}, following {:.0f} ms",
                  frame_index, ms(requested, detection_start), ms(detection_start, detection_end),
                  ms(detection_end, process_start), ms(process_start, process_end), ms(process_end, Clock::now()));
  }
};

/// Keyframe jobs allowed in flight (running + queued) before a new one is deferred:
/// the tracker never waits, and a slow back end does not pile up stale keyframes.
constexpr size_t kMaxPendingKeyframes = 2;

/// Frames whose pyramids are kept to bring a late keyframe's points up to date.
constexpr size_t kMaxBufferedPyramids = 40;

lines::LineTrackerConfig plain_scene_tracker(const VoConfig& config) {
  lines::LineTrackerConfig c = config.lines.tracker;
  if (c.aperture_max_eigen_ratio <= 0) c.aperture_max_eigen_ratio = config.plain_scene.line_aperture_eigen_ratio;
  return c;
}

}  // namespace

using namespace odometry_detail;

Odometry::Odometry(const VoConfig& config, const io::Calibration& calibration, bool use_stereo, bool use_depth,
                   RunStats& stats)
    : config_(config.for_mode((use_stereo && calibration.stereo()) || (use_depth && calibration.has_depth()))),
      stats_(stats),
      rectifier_(calibration, use_stereo && calibration.stereo(), use_depth && calibration.has_depth(),
                 parse_working_view(config_.frontend.working_view)),
      camera_(rectifier_.camera()),
      tracker_(config_.klt),
      use_lines_(config_.pipeline.lines),
      redetect_lines_(config_.pipeline.line_tracking == "redetect"),
      line_tracker_(config_.lines.tracker),
      plain_line_tracker_(plain_scene_tracker(config_)),
      line_detector_(config_.lines.detector),
      use_directions_(use_lines_ && (metric() ? config_.directions.stereo : config_.directions.mono)),
      directions_(config_.directions),
      policy_(config_.keyframes),
      processor_(config_, camera_, rectifier_.depth() ? config_.depth.virtual_baseline_m : rectifier_.baseline(), map_,
                 stats, rectifier_.depth()),
      worker_(config.run.threaded, config.run.keyframe_stages, config.run.keyframe_worker_nice) {
  // The networks run on the keyframe worker beside tracking; a single-thread run stays on one.
  if (processor_.frontend_name() == "superpoint")
    nn::set_num_threads(config_.run.threaded ? config_.run.network_threads : 1);
  spdlog::debug("working view {}x{}: fx {:.1f} fy {:.1f} cx {:.1f} cy {:.1f}", camera_.width, camera_.height, camera_.fx,
                camera_.fy, camera_.cx, camera_.cy);
  T_work_cam0_ = rectifier_.T_cam0_work().inverse();
  // The world frame is cam0 of the first initialised frame.
  T_world_work_ = rectifier_.T_cam0_work();
}

Odometry::~Odometry() = default;

geometry::Pose Odometry::to_output(const geometry::Pose& T_world_work) const { return T_world_work * T_work_cam0_; }

void Odometry::normalize_brightness(cv::Mat& left, cv::Mat& right) const {
  // LK assumes constant brightness; flicker, exposure jumps and auto exposure break that by
  // a gain common to the whole frame (and to both cameras of a pair). One gain that brings
  // the frame's mean to a fixed level removes it; the NCC check is gain-invariant anyway.
  const double target = config_.klt.normalize_mean;
  if (target <= 0 || frame_brightness_ < 1.0) return;
  const double gain = std::clamp(target / frame_brightness_, 1.0 / config_.klt.max_normalize_gain,
                                 config_.klt.max_normalize_gain);
  if (std::abs(gain - 1.0) < 0.02) return;
  cv::Mat l, r;
  left.convertTo(l, CV_8U, gain);
  left = l;
  if (!right.empty()) {
    right.convertTo(r, CV_8U, gain);
    right = r;
  }
}

double Odometry::denoise(cv::Mat& left, cv::Mat& right) {
  const double sigma = config_.klt.denoise_sigma_px;
  const double noise = estimate_noise_sigma(left);
  stats_.add_sample("image_noise", noise);
  if (config_.klt.denoise_min_noise <= 0 || sigma <= 0 || noise < config_.klt.denoise_min_noise) return noise;
  cv::Mat l, r;
  cv::GaussianBlur(left, l, cv::Size(), sigma);
  left = l;
  if (!right.empty()) {
    cv::GaussianBlur(right, r, cv::Size(), sigma);
    right = r;
  }
  stats_.add_count("denoised_frames");
  return noise;
}

FrameRecord Odometry::process(const io::Frame& frame) {
  ScopedTimer total(stats_, "frame");
  FrameRecord record;
  record.index = frame.index;
  record.timestamp = frame.timestamp;
  cv::Mat left, right;
  {
    ScopedTimer t(stats_, "rectify");
    rectifier_.apply(frame, left, right, frame_depth_);
    frame_brightness_ = cv::mean(left)[0];
    normalize_brightness(left, right);
    frame_noise_ = denoise(left, right);
  }
  ImagePyramid pyramid;
  {
    ScopedTimer t(stats_, "pyramid");
    pyramid = use_lines_ ? tracker_.build_pyramid(left, config_.lines.tracker.window_px,
                                                  config_.lines.tracker.max_pyramid_level)
                         : tracker_.build_pyramid(left);
  }
  if (config_.run.wait_when_starving && state_ == TrackingState::kTracking && !worker_.idle() &&
      count_mapped(tracks_) < config_.run.starving_points_at(frame_noise_)) {
    ScopedTimer t(stats_, "starved_wait");
    worker_.wait_idle();
    stats_.add_count("starved_waits");
  }
  worker_.rethrow_if_failed();
  apply_keyframe_results();
  if (state_ == TrackingState::kUninitialized) apply_start_outcome(frame.index);

  bool tracked = false;
  bool reference = true;  // this frame is the next one's KLT reference
  if (state_ == TrackingState::kTracking) {
    // The tracks as they are in the reference frame, restored if this frame does not become it.
    std::vector<TrackedPoint> points = tracks_;
    std::vector<TrackedLine> lines = line_tracks_;
    std::vector<FrameCorner> corners = corners_;
    tracked = track_or_restart(frame, left, right, pyramid, record);
    if (!tracked && keeps_reference_over_failure()) {
      tracks_ = std::move(points);
      line_tracks_ = std::move(lines);
      corners_ = std::move(corners);
      reference = false;
      stats_.add_count("failed_frames_not_reference");
    }
  } else {
    tracked = initialize(frame, left, right, pyramid);
  }

  if (reference) {
    if (!pending_keyframe_frames_.empty()) pyramid_buffer_.push(frame.index, pyramid, kMaxBufferedPyramids);
    previous_pyramid_ = pyramid;
  }
  previous_image_ = left;
  previous_index_ = frame.index;

  record.tracked = tracked;
  record.segment = processor_.segment();
  if (tracked) {
    last_tracked_index_ = frame.index;
    last_tracked_time_ = frame.timestamp;
    record.T_world_cam = to_output(T_world_work_);
    if (record.tracked_points == 0) record.tracked_points = count_mapped(tracks_);
  }
  stats_.add_count("frames");
  if (tracked) stats_.add_count("tracked_frames");
  stats_.add_sample("tracked_points", record.tracked_points);
  stats_.add_sample("tracked_lines", record.tracked_lines);
  records_.push_back(record);
  return record;
}

TrackingView Odometry::tracking_view() const {
  TrackingView view;
  view.frame_index = previous_index_;
  view.tracked = !records_.empty() && records_.back().tracked;
  view.image = previous_image_;
  if (state_ == TrackingState::kTracking) {
    view.points = tracks_;
    view.lines = line_tracks_;
  }
  return view;
}

// ---------------------------------------------------------------- initialisation

KeyframeJob Odometry::make_keyframe_job(const io::Frame& frame, const cv::Mat& left,
                                        const cv::Mat& right, const ImagePyramid& pyramid,
                                        KeyframeReason reason) const {
  KeyframeJob job;
  job.frame_index = frame.index;
  job.timestamp = frame.timestamp;
  job.left = left;
  job.right = right;
  job.depth = frame_depth_;
  job.left_pyramid = pyramid;
  job.T_world_cam = T_world_work_;
  job.reason = reason;
  job.image_noise = frame_noise_;
  job.directions = frame_directions_;
  if (detected_lines_ && detected_lines_frame_ == frame.index) job.line_detections = detected_lines_;
  return job;
}

void Odometry::maybe_make_keyframe(const io::Frame& frame, const cv::Mat& left, const cv::Mat& right,
                                   const ImagePyramid& pyramid, int tracked_points) {
  ScopedTimer t(stats_, "keyframe_decision");
  FrameTrackingState state;
  state.timestamp = frame.timestamp;
  state.tracked_points = tracked_points;
  state.backend_idle = worker_.idle();
  state.keyframe_in_flight = !pending_keyframe_frames_.empty();
  state.line_angle_distance_deg = line_angle_distance();
  const KeyframeReason reason = policy_.decide(state);
  if (reason == KeyframeReason::kNone) return;
  if (!worker_.idle()) stats_.add_count("keyframes_requested_while_busy");
  if (worker_.pending() >= kMaxPendingKeyframes) {
    const bool degrading = reason == KeyframeReason::kFewPoints || reason == KeyframeReason::kTrackingQuality;
    if (!(degrading && config_.run.wait_when_starving)) {
      stats_.add_count("keyframes_deferred");
      return;
    }
    // Tracking is running out of points and the back end is behind: with offline input,
    // waiting for it costs throughput only, while tracking on keeps thinning the points
    // until the pose drifts or is lost.
    ScopedTimer wait(stats_, "starved_wait");
    worker_.wait_idle();
    stats_.add_count("starved_waits");
  }
  KeyframeJob job = make_keyframe_job(frame, left, right, pyramid, reason);
  job.tracks = tracks_;
  job.lines = line_tracks_;
  policy_.start_keyframe(frame.timestamp, tracked_points);
  submit_keyframe(std::move(job));
}

void Odometry::submit_keyframe(KeyframeJob job) {
  stats_.add_count("keyframe_requests");
  pending_keyframe_frames_.insert(job.frame_index);
  // Two parts (KeyframeWorker): detection, then the rest with what it found.
  auto shared_job = std::make_shared<const KeyframeJob>(std::move(job));
  auto detected = std::make_shared<DetectedKeyframe>();
  auto timeline = std::make_shared<KeyframeTimeline>();
  keyframe_requested_at_[shared_job->frame_index] = timeline->requested;
  worker_.submit(
      [this, shared_job, detected, timeline] {
        timeline->detection_start = KeyframeTimeline::Clock::now();
        *detected = processor_.detect_keyframe(*shared_job);
        timeline->detection_end = KeyframeTimeline::Clock::now();
      },
      [this, shared_job, detected, timeline] {
        timeline->process_start = KeyframeTimeline::Clock::now();
        KeyframeResult result = processor_.process(*shared_job, std::move(*detected));
        timeline->process_end = KeyframeTimeline::Clock::now();
        if (result.ok) {
          ScopedTimer t(stats_, "kf_catch_up");
          prepare_result(*shared_job, result);
        }
        timeline->log(shared_job->frame_index);
        std::lock_guard<std::mutex> lock(results_mutex_);
        results_.push_back(std::move(result));
      });
}

void Odometry::finish() {
  worker_.wait_idle();
  worker_.rethrow_if_failed();
  apply_keyframe_results();
  // A live start that came back after the last frame still gives the frames since its own their poses.
  if (state_ == TrackingState::kUninitialized && !records_.empty()) apply_start_outcome(previous_index_ + 1);
}

io::Trajectory Odometry::keyframe_trajectory() const { return vo::keyframe_trajectory(keyframe_poses()); }

std::vector<KeyframePose> Odometry::keyframe_poses() const {
  std::vector<KeyframePose> poses;
  map_.read([&](const MapData& m) {
    for (const auto& [id, kf] : m.keyframes)
      poses.push_back({kf.frame_index, kf.timestamp, kf.segment, to_output(kf.T_world_cam)});
  });
  return poses;
}

MapData Odometry::map_snapshot() const {
  // The working camera differs from cam0 by a rotation only, and the world is defined in
  // cam0 terms already (T_world_work includes T_cam0_work), so map coordinates are output coordinates.
  return map_.read([](const MapData& m) { return m; });
}

}  // namespace pllvo::vo
