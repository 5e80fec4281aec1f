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

namespace pllvo::vo {
namespace {

/// Keyframe jobs allowed in flight (running + queued) before a new one is deferred:
/// the tracker never waits, and a slow back end does not pile up stale keyframes.
constexpr size_t kMaxPendingKeyframes = 2;
/// Frames whose pyramids are kept to bring a late keyframe's points up to date.
constexpr size_t kMaxBufferedPyramids = 40;

Eigen::Vector2d to_eigen(const cv::Point2f& p) { return {p.x, p.y}; }

int count_mapped(const std::vector<TrackedPoint>& tracks) {
  return static_cast<int>(
      std::count_if(tracks.begin(), tracks.end(), [](const TrackedPoint& t) { return t.point != kNoId; }));
}

lines::LineTrackerConfig plain_scene_tracker(const VoConfig& config) {
  lines::LineTrackerConfig c = config.lines.tracker;
  if (c.aperture_max_eigen_ratio <= 0) c.aperture_max_eigen_ratio = config.plain_scene.line_aperture_eigen_ratio;
  return c;
}

size_t count_mapped_lines(const std::vector<TrackedLine>& lines) {
  return static_cast<size_t>(
      std::count_if(lines.begin(), lines.end(), [](const TrackedLine& l) { return l.line != kNoId; }));
}

/// Re-detection baseline (pipeline.line_tracking: redetect): each expected segment takes the
/// detection on the same image line (direction within kRedetectAngleDeg, both detected
/// endpoints within kRedetectDistancePx of the expected line, overlapping along it), closest
/// first, one to one.
constexpr double kRedetectAngleDeg = 5.0;
constexpr double kRedetectDistancePx = 6.0;

std::vector<int> associate_by_position(const std::vector<lines::LineSegment>& expected,
                                       const std::vector<lines::LineSegment>& detections) {
  struct Pair {
    double score;
    int e, d;
  };
  std::vector<Pair> pairs;
  const double max_angle = kRedetectAngleDeg * M_PI / 180.0;
  for (int e = 0; e < static_cast<int>(expected.size()); ++e) {
    const auto& x = expected[e];
    for (int d = 0; d < static_cast<int>(detections.size()); ++d) {
      const auto& y = detections[d];
      if (lines::acute_angle(x, y) > max_angle) continue;
      const double ds = std::abs(lines::signed_line_distance(y.start, x)),
                   de = std::abs(lines::signed_line_distance(y.end, x));
      if (std::max(ds, de) > kRedetectDistancePx) continue;
      const double s0 = lines::project_along(y.start, x), s1 = lines::project_along(y.end, x);
      if (std::min(x.length(), std::max(s0, s1)) - std::max(0.0, std::min(s0, s1)) <= 0) continue;
      pairs.push_back({ds + de + (x.midpoint() - y.midpoint()).norm() * 0.1, e, d});
    }
  }
  std::sort(pairs.begin(), pairs.end(), [](const Pair& a, const Pair& b) { return a.score < b.score; });
  std::vector<int> out(expected.size(), -1);
  std::vector<char> used(detections.size(), 0);
  for (const auto& p : pairs)
    if (out[p.e] < 0 && !used[p.d]) out[p.e] = p.d, used[p.d] = 1;
  return out;
}

/// Weight of a map point's residual in a monocular pose (pose.mono_point_uncertainty_px):
/// 1 / sqrt(1 + (s / scale_px)^2), s the pixels its depth uncertainty moves it in the camera.
double uncertainty_weight(const MapData& m, const MapPoint& point, const Pinhole& camera,
                          const geometry::Pose& T_world_cam, double scale_px) {
  std::vector<Eigen::Vector3d> centres;
  for (const auto& o : point.observations)
    if (auto kf = m.keyframes.find(o.keyframe); kf != m.keyframes.end())
      centres.push_back(kf->second.T_world_cam.translation());
  const double s = depth_uncertainty_px(camera, point.position, centres, T_world_cam) / scale_px;
  return 1.0 / std::sqrt(1.0 + s * s);
}

}  // namespace

Odometry::Odometry(const VoConfig& config, const io::Calibration& calibration, bool use_stereo, RunStats& stats)
    : config_(config.for_mode(use_stereo && calibration.stereo())),
      stats_(stats),
      rectifier_(calibration, use_stereo && calibration.stereo(),
                 parse_working_view(config_.frontend.working_view)),
      camera_(rectifier_.camera()),
      tracker_(config_.klt),
      use_lines_(config_.pipeline.lines),
      redetect_lines_(config_.pipeline.line_tracking == "redetect"),
      line_tracker_(config_.lines.tracker),
      plain_line_tracker_(plain_scene_tracker(config_)),
      line_detector_(config_.lines.detector),
      use_directions_(use_lines_ && (rectifier_.stereo() ? config_.directions.stereo : config_.directions.mono)),
      directions_(config_.directions),
      policy_(config_.keyframes),
      processor_(config_, camera_, rectifier_.baseline(), map_, stats),
      worker_(config.run.threaded, config.run.keyframe_stages) {
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
    rectifier_.apply(frame, left, right);
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

  bool tracked = false;
  if (state_ == TrackingState::kTracking)
    tracked = track_or_restart(frame, left, right, pyramid, record);
  else
    tracked = initialize(frame, left, right, pyramid);

  if (!pending_keyframe_frames_.empty()) pyramid_buffer_.push(frame.index, pyramid, kMaxBufferedPyramids);
  previous_pyramid_ = pyramid;
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

bool Odometry::initialize(const io::Frame& frame, const cv::Mat& left, const cv::Mat& right,
                          const ImagePyramid& pyramid, std::optional<DetectedKeyframe> detected, bool* relocalised) {
  ScopedTimer t(stats_, "init");
  if (frame_brightness_ < config_.init.min_brightness) {
    mono_.reset();
    return false;
  }
  return rectifier_.stereo() ? initialize_stereo(frame, left, right, pyramid, std::move(detected), relocalised)
                             : initialize_mono(frame, left, pyramid);
}

KeyframeJob Odometry::make_keyframe_job(const io::Frame& frame, const cv::Mat& left,
                                        const cv::Mat& right, const ImagePyramid& pyramid,
                                        KeyframeReason reason) const {
  KeyframeJob job;
  job.frame_index = frame.index;
  job.timestamp = frame.timestamp;
  job.left = left;
  job.right = right;
  job.left_pyramid = pyramid;
  job.T_world_cam = T_world_work_;
  job.reason = reason;
  job.image_noise = frame_noise_;
  job.directions = frame_directions_;
  if (detected_lines_ && detected_lines_frame_ == frame.index) job.line_detections = detected_lines_;
  return job;
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
  spdlog::info("stereo initialisation at frame {}: {} points{}", frame.index, result.tracks.size(),
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
  start_tracking(result, frame.timestamp, two_view.model);
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

void Odometry::start_tracking(const KeyframeResult& result, double timestamp, const std::string& start_model) {
  state_ = TrackingState::kTracking;
  map_start_time_ = timestamp;
  map_start_model_ = start_model;
  tracks_ = result.tracks;
  line_tracks_ = result.lines;
  set_reference_lines(line_tracks_);
  has_velocity_ = false;
  velocity_ = geometry::Pose::Identity();
  lost_frames_ = 0;
  policy_.start_keyframe(timestamp, count_mapped(tracks_));
}

// ---------------------------------------------------------------- tracking

void Odometry::retrack_on_local_contrast(const cv::Mat& left, const std::vector<cv::Point2f>& from,
                                         const std::vector<cv::Point2f>& predicted, TrackResult& tr) {
  const double share = config_.klt.contrast_fallback_share;
  if (share <= 0 || from.empty() || previous_image_.empty() ||
      tr.tracked() >= share * static_cast<double>(from.size()))
    return;
  const int window = config_.klt.contrast_window_px;
  const ImagePyramid a = tracker_.build_pyramid(local_contrast(previous_image_, window));
  const ImagePyramid b = tracker_.build_pyramid(local_contrast(left, window));
  TrackResult again = tracker_.track(a, b, from, &predicted);
  stats_.add_count("klt_contrast_fallbacks");
  if (again.tracked() > tr.tracked()) {
    spdlog::debug("KLT on local contrast: {} of {} tracks instead of {}", again.tracked(), from.size(), tr.tracked());
    tr = std::move(again);
  }
}

bool Odometry::track_or_restart(const io::Frame& frame, const cv::Mat& left, const cv::Mat& right,
                                const ImagePyramid& pyramid, FrameRecord& record) {
  if (track(frame, left, right, pyramid, record)) return true;
  handle_lost();
  if (!config_.pose.stereo_restart_at_once || !rectifier_.stereo()) return false;
  std::optional<DetectedKeyframe> detected;
  if (state_ == TrackingState::kTracking) {
    // Coasting on the tracks left sometimes gets the pose back a frame later in the same map,
    // so the map is only given up for a restart that this frame places in it. The start
    // below reuses the features detected for the try.
    if (config_.pose.relocalise_min_inliers <= 0) return false;
    // Live input (run.wait_when_starving off) never waits: the try is made on a later frame
    // that finds the worker idle.
    if (!config_.run.wait_when_starving && !worker_.idle()) return false;
    worker_.wait_idle();
    worker_.rethrow_if_failed();
    const KeyframeJob job = make_keyframe_job(frame, left, right, pyramid, KeyframeReason::kNone);
    detected = processor_.detect_keyframe(job);
    if (!processor_.relocalise_in_segment(job, *detected)) return false;
    reset();
  }
  bool relocalised = false;
  if (initialize(frame, left, right, pyramid, std::move(detected), &relocalised) && relocalised) {
    stats_.add_count("restarts_relocalised_at_once");
    return true;  // the relocalised pose is this frame's
  }
  return false;
}

bool Odometry::track(const io::Frame& frame, const cv::Mat& left, const cv::Mat& right,
                     const ImagePyramid& pyramid, FrameRecord& record) {
  const geometry::Pose T_world_pred =
      config_.pose.use_motion_prior && has_velocity_ ? T_world_work_ * velocity_ : T_world_work_;
  const geometry::Pose T_pred_world = T_world_pred.inverse();

  std::vector<Eigen::Vector3d> positions(tracks_.size());
  std::vector<unsigned char> known(tracks_.size(), 0);
  // Monocular: a map point's depth uncertainty in this image, from its keyframes' rays.
  const double uncertainty_px = rectifier_.stereo() ? 0.0 : config_.pose.mono_point_uncertainty_px;
  std::vector<double> weights(uncertainty_px > 0 ? tracks_.size() : 0, 1.0);
  // Monocular: tracks without a map point constrain the rotation and the direction of motion
  // since their first keyframe (pose.mono_epipolar_weight).
  PoseExtras extras;
  extras.epipolar_weight =
      rectifier_.stereo()
          ? 0.0
          : config_.pose.epipolar_weight_at(frame.timestamp - map_start_time_, map_start_model_, frame_noise_);
  std::vector<std::optional<FeatureView>> first_view(tracks_.size());
  map_.read([&](const MapData& m) {
    for (size_t i = 0; i < tracks_.size(); ++i) {
      auto it = m.points.find(tracks_[i].point);
      if (it == m.points.end()) {
        if (extras.epipolar_weight > 0) first_view[i] = m.feature_view(tracks_[i].origin);
        continue;
      }
      positions[i] = it->second.position, known[i] = 1;
      if (!weights.empty()) weights[i] = uncertainty_weight(m, it->second, camera_, T_world_pred, uncertainty_px);
    }
  });
  std::vector<cv::Point2f> from, predicted;
  for (size_t i = 0; i < tracks_.size(); ++i) {
    from.push_back(tracks_[i].px);
    Eigen::Vector2d uv;
    if (known[i] && camera_.project(T_pred_world * positions[i], uv) && camera_.inside(uv))
      predicted.emplace_back(static_cast<float>(uv.x()), static_cast<float>(uv.y()));
    else
      predicted.push_back(tracks_[i].px);
  }
  TrackResult tr;
  {
    ScopedTimer t(stats_, "klt");
    tr = tracker_.track(previous_pyramid_, pyramid, from, &predicted);
    retrack_on_local_contrast(left, from, predicted, tr);
  }
  stats_.add_count("klt_rejected.lk", tr.rejected.lk);
  stats_.add_count("klt_rejected.border", tr.rejected.border);
  stats_.add_count("klt_rejected.forward_backward", tr.rejected.forward_backward);
  stats_.add_count("klt_rejected.appearance", tr.rejected.appearance);

  // Lines: predicted from their 3-D segment when they have one, followed by line optical flow.
  std::vector<LineMeasurement> line_measurements;
  std::vector<size_t> measured_lines;  // index in line_tracks_ per measurement
  if (use_lines_ && !line_tracks_.empty()) {
    ScopedTimer t(stats_, "line_tracking");
    std::vector<lines::LineSegment> predicted_lines;
    std::vector<std::optional<std::pair<Eigen::Vector3d, Eigen::Vector3d>>> ends(line_tracks_.size());
    map_.read([&](const MapData& m) {
      for (size_t i = 0; i < line_tracks_.size(); ++i) {
        auto it = m.lines.find(line_tracks_[i].line);
        if (it != m.lines.end()) ends[i] = std::make_pair(it->second.p, it->second.q);
      }
    });
    for (size_t i = 0; i < line_tracks_.size(); ++i) {
      lines::LineSegment p = line_tracks_[i].segment;
      Eigen::Vector2d a, b;
      if (ends[i] && camera_.project(T_pred_world * ends[i]->first, a) &&
          camera_.project(T_pred_world * ends[i]->second, b) && camera_.inside(a) && camera_.inside(b)) {
        // The tracked segment's extent, moved onto the predicted image line.
        const lines::LineSegment image_line(a, b);
        const double sa = lines::project_along(p.start, image_line), sb = lines::project_along(p.end, image_line);
        if (image_line.length() > 1) p.start = image_line.at(sa / image_line.length()), p.end = image_line.at(sb / image_line.length());
      }
      predicted_lines.push_back(p);
    }
    const size_t mapped_before = count_mapped_lines(line_tracks_);
    const bool plain = plain_frame();
    if (plain) stats_.add_count("plain_scene_line_frames");
    const std::vector<lines::LineSegment>* detections =
        redetect_lines_ && !line_tracks_.empty() ? &frame_lines(pyramid.image, frame.index) : nullptr;
    line_tracks_ = track_lines(previous_pyramid_, pyramid, line_tracks_, plain, &predicted_lines, detections);
    spdlog::debug("frame {}: line flow kept {} of {} mapped lines ({} lines in all)", frame.index,
                  count_mapped_lines(line_tracks_), mapped_before, line_tracks_.size());
    if (config_.pose.use_lines) {
      map_.read([&](const MapData& m) {
        for (size_t i = 0; i < line_tracks_.size(); ++i) {
          auto it = m.lines.find(line_tracks_[i].line);
          if (it == m.lines.end()) continue;
          line_measurements.push_back({it->second.p, it->second.q, to_segment2d(line_tracks_[i].segment)});
          measured_lines.push_back(i);
        }
      });
    }
  }

  std::vector<size_t> which;
  std::vector<Eigen::Vector3d> pts;
  std::vector<Eigen::Vector2d> px;
  for (size_t i = 0; i < tracks_.size(); ++i) {
    if (!tr.ok[i] || !known[i]) continue;
    which.push_back(i);
    pts.push_back(positions[i]);
    px.push_back(to_eigen(tr.points[i]));
    if (!weights.empty()) extras.point_weights.push_back(weights[i]);
  }
  const double full_weight_deg = config_.pose.mono_epipolar_full_weight_deg;
  const double depth = extras.epipolar_weight > 0 && full_weight_deg > 0 ? median_depth(pts, T_world_pred) : 0.0;
  for (size_t i = 0; i < tracks_.size(); ++i)
    if (first_view[i] && tr.ok[i])
      extras.epipolar.push_back({first_view[i]->T_world_cam, camera_.normalised(first_view[i]->px),
                                 camera_.normalised(to_eigen(tr.points[i])),
                                 epipolar_track_weight(first_view[i]->T_world_cam, T_world_pred, depth, full_weight_deg)});

  std::vector<DirectionSegment> dir_segments;
  if (use_directions_) {
    ScopedTimer t(stats_, "direction_lines");
    dir_segments = direction_segments(pyramid.image, frame.index);
    extras.directions = direction_observations(dir_segments, T_pred_world.linear());
    extras.direction_weight = config_.directions.weight;
    stats_.add_count("direction_observations", static_cast<long long>(extras.directions.size()));
    spdlog::debug("frame {}: {} of {} detected segments on {} known directions", frame.index, extras.directions.size(),
                  dir_segments.size(), directions_.directions().size());
  }

  PoseEstimate estimate;
  {
    ScopedTimer t(stats_, "pose");
    std::optional<geometry::Pose> predicted;
    if (config_.pose.use_motion_prior && has_velocity_) predicted = T_world_pred;
    estimate = estimate_pose(camera_, pts, px, line_measurements, predicted, config_.geometry, config_.backend, extras);
    if (!estimate.ok && config_.pose.use_motion_prior && config_.pose.min_inliers_with_prior > 0) {
      // Too few points for PnP (a textureless stretch): the constant-velocity prediction
      // carries the pose while a few observations (points and lines) still agree with it.
      // Right after a start there is no velocity yet: T_world_pred is the last pose (no motion).
      backend::BackendConfig weak = config_.backend;
      weak.pose_refiner.min_inliers = config_.pose.min_inliers_with_prior;
      estimate = estimate_pose(camera_, pts, px, line_measurements, T_world_pred, config_.geometry, weak, extras);
      if (estimate.ok) stats_.add_count("prior_supported_poses");
    }
    const bool by_frame_motion = !estimate.ok;
    if (by_frame_motion) estimate = pose_from_frame_motion(frame.index, from, tr, which, line_measurements.size());
    frame_motion_run_ = estimate.ok && by_frame_motion ? frame_motion_run_ + 1 : 0;
    if (estimate.ok && by_frame_motion) {
      stats_.add_count("frame_motion_poses");
      stats_.add_sample("frame_motion_run", frame_motion_run_);  // its max: the longest run in a row
    }
  }

  // Keep the tracks that survived KLT (and, on success, the pose's inlier test); candidates
  // (no map point yet) only need KLT.
  std::vector<TrackedPoint> kept;
  for (size_t k = 0; k < which.size(); ++k) {
    if (estimate.ok && !estimate.point_inliers[k]) continue;
    TrackedPoint tp = tracks_[which[k]];
    tp.px = tr.points[which[k]];
    kept.push_back(tp);
  }
  for (size_t i = 0; i < tracks_.size(); ++i) {
    if (known[i] || tracks_[i].point != kNoId || !tr.ok[i]) continue;
    TrackedPoint tp = tracks_[i];
    tp.px = tr.points[i];
    kept.push_back(tp);
  }
  tracks_ = std::move(kept);
  if (estimate.ok) {
    // Lines whose 3-D segment disagrees with the pose lose the link (their track may be off).
    std::vector<char> drop(line_tracks_.size(), 0);
    for (size_t k = 0; k < measured_lines.size(); ++k)
      if (!estimate.line_inliers[k]) drop[measured_lines[k]] = 1;
    std::vector<TrackedLine> kept_lines;
    for (size_t i = 0; i < line_tracks_.size(); ++i)
      if (!drop[i]) kept_lines.push_back(line_tracks_[i]);
    line_tracks_ = std::move(kept_lines);
  }
  spdlog::debug("frame {}: {} map points followed, {} pose inliers, {} tracks kept; {} of {} 3-D lines agree",
                frame.index, pts.size(), estimate.ok ? estimate.num_point_inliers : 0, tracks_.size(),
                estimate.ok ? estimate.num_line_inliers : 0, line_measurements.size());

  if (!estimate.ok) {
    spdlog::debug("frame {}: pose failed ({} tracked points)", frame.index, pts.size());
    return false;
  }
  const geometry::Pose T_world_cur = estimate.T_world_cam;
  frame_directions_.clear();
  if (use_directions_) {
    // The segments at the estimated pose: a keyframe of this frame takes them to the window.
    const Eigen::Matrix3d R_cam_world = T_world_cur.linear().transpose();
    frame_directions_ = direction_observations(dir_segments, R_cam_world);
    const int added = directions_.discover(dir_segments, R_cam_world, camera_.focal());
    if (added > 0) {
      stats_.add_count("directions_added", added);
      const Eigen::Vector3d& d = directions_.directions().back();
      spdlog::debug("frame {}: {} new directions ({} known), last {:.4f} {:.4f} {:.4f}", frame.index, added,
                    directions_.directions().size(), d.x(), d.y(), d.z());
    }
  }
  velocity_ = T_world_work_.inverse() * T_world_cur;
  // After lost frames the step spans several frames: do not extrapolate it.
  has_velocity_ = lost_frames_ == 0;
  T_world_work_ = T_world_cur;
  lost_frames_ = 0;
  remember_position(frame.index, T_world_cur.translation());
  record.tracked_points = estimate.num_point_inliers;
  record.tracked_lines = estimate.num_line_inliers;

  maybe_make_keyframe(frame, left, right, pyramid, estimate.num_point_inliers);
  return true;
}

PoseEstimate Odometry::pose_from_frame_motion(size_t frame_index, const std::vector<cv::Point2f>& from,
                                              const TrackResult& tr, const std::vector<size_t>& map_tracks,
                                              size_t num_lines) const {
  const PoseConfig& c = config_.pose;
  PoseEstimate est;
  // The previous frame must have its pose: the motion is measured from it.
  if (rectifier_.stereo() || c.mono_frame_motion_min_inliers <= 0 || !has_velocity_ || lost_frames_ > 0 ||
      frame_motion_run_ >= c.mono_frame_motion_max_frames)
    return est;
  std::vector<Eigen::Vector2d> xy0, xy1;
  std::vector<int> match_of_track(from.size(), -1);
  for (size_t i = 0; i < from.size(); ++i) {
    if (!tr.ok[i]) continue;
    match_of_track[i] = static_cast<int>(xy0.size());
    xy0.push_back(camera_.normalised(to_eigen(from[i])));
    xy1.push_back(camera_.normalised(to_eigen(tr.points[i])));
  }
  geometry::RelativeMotionLimits limits;
  limits.min_inliers = c.mono_frame_motion_min_inliers;
  limits.max_rotation_change_deg = c.mono_frame_motion_max_rotation_change_deg;
  limits.max_translation_change_deg = c.mono_frame_motion_max_translation_change_deg;
  limits.translation_prior_sigma_deg = c.mono_frame_motion_translation_sigma_deg;
  const geometry::RelativeMotion m = geometry::estimate_relative_motion(
      xy0, xy1, camera_.focal(), velocity_.inverse(), limits, config_.geometry.two_view);
  spdlog::debug("frame {}: motion from the previous frame {}: {} of {} tracks fit, {:.1f} deg from the last "
                "rotation, {:.0f} deg from the last direction{}{}{}",
                frame_index, m.ok ? "taken" : "refused", m.num_inliers, xy0.size(), m.rotation_from_expected_deg,
                m.translation_from_expected_deg, m.translation_kept ? " (direction kept)" : "", m.ok ? "" : ": ",
                m.failure);
  if (!m.ok) return est;
  geometry::Pose T_cur_prev = m.T_cam1_cam0;
  T_cur_prev.translation() *= velocity_.translation().norm();
  est.ok = true;
  est.T_world_cam = T_world_work_ * T_cur_prev.inverse();
  for (size_t i : map_tracks) {
    const bool inlier = match_of_track[i] >= 0 && m.inliers[match_of_track[i]];
    est.point_inliers.push_back(inlier);
    est.num_point_inliers += inlier;
  }
  // The map's lines were not part of this estimate: keep their tracks for the next frame.
  est.line_inliers.assign(num_lines, 1);
  return est;
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
  state.candidate_parallax_deg = candidate_parallax_deg();
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
  worker_.submit([this, shared_job, detected] { *detected = processor_.detect_keyframe(*shared_job); },
                 [this, shared_job, detected] {
                   KeyframeResult result = processor_.process(*shared_job, std::move(*detected));
                   if (result.ok) {
                     ScopedTimer t(stats_, "kf_catch_up");
                     prepare_result(*shared_job, result);
                   }
                   std::lock_guard<std::mutex> lock(results_mutex_);
                   results_.push_back(std::move(result));
                 });
}

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
      const TrackResult tr = tracker_.track(from, to, pts);
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

void Odometry::prepare_result(const KeyframeJob& job, KeyframeResult& result) const {
  auto point_id = [](const TrackedPoint& p) { return p.point; };
  auto line_id = [](const TrackedLine& l) { return l.line; };
  const auto point_index = index_by_identity(job.tracks, point_id);
  const auto line_index = index_by_identity(job.lines, line_id);
  for (const auto& r : result.tracks)
    if (!find_identity(point_index, r, point_id)) result.new_tracks.push_back(r);
  for (const auto& r : result.lines)
    if (!find_identity(line_index, r, line_id)) result.new_lines.push_back(r);
  std::vector<std::pair<size_t, ImagePyramid>> frames = {{job.frame_index, job.left_pyramid}};
  for (auto& f : pyramid_buffer_.from(job.frame_index + 1)) frames.push_back(std::move(f));
  follow(frames, result.new_tracks, result.new_lines);
  result.followed_frame = frames.back().first;
}

void Odometry::apply_keyframe_results() {
  std::deque<KeyframeResult> ready;
  {
    std::lock_guard<std::mutex> lock(results_mutex_);
    ready.swap(results_);
  }
  for (auto& result : ready) {
    pending_keyframe_frames_.erase(result.frame_index);
    if (!result.ok || state_ != TrackingState::kTracking) continue;
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
      merged.push_back({tracks_[*i].px, r.point, r.origin, r.last});
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
      std::vector<std::pair<size_t, ImagePyramid>> frames;
      for (auto& f : pyramid_buffer_.from(result.followed_frame))
        if (f.first <= previous_index_) frames.push_back(std::move(f));
      if (frames.empty() || frames.front().first != result.followed_frame) {
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
  if (gate <= 0) return;
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

std::vector<TrackedLine> Odometry::track_lines(const ImagePyramid& from, const ImagePyramid& to,
                                               const std::vector<TrackedLine>& lines,
                                               bool plain,
                                               const std::vector<lines::LineSegment>* predicted,
                                               const std::vector<lines::LineSegment>* detected) const {
  if (lines.empty()) return {};
  std::vector<lines::LineSegment> segments;
  segments.reserve(lines.size());
  for (const auto& l : lines) segments.push_back(l.segment);
  if (redetect_lines_) {
    if (!detected) return {};
    stats_.add_count("line_redetections");
    const std::vector<lines::LineSegment> detections =
        config_.lines.cross_constraint.enabled ? lines::apply_cross_constraint(*detected, config_.lines.cross_constraint)
                                               : *detected;
    const auto assignment = associate_by_position(predicted ? *predicted : segments, detections);
    std::vector<TrackedLine> kept;
    for (size_t i = 0; i < lines.size(); ++i) {
      if (assignment[i] < 0) continue;
      TrackedLine l = lines[i];
      l.segment = detections[assignment[i]];
      kept.push_back(l);
    }
    return kept;
  }
  const auto tracks = (plain ? plain_line_tracker_ : line_tracker_).track(from.flow, to.flow, segments, predicted);
  std::vector<TrackedLine> kept;
  for (size_t i = 0; i < tracks.size(); ++i) {
    if (tracks[i].status != lines::TrackStatus::Tracked) {
      stats_.add_count(std::string("line_rejected.") + lines::to_string(tracks[i].status));
      continue;
    }
    TrackedLine l = lines[i];
    l.segment = tracks[i].line;
    kept.push_back(l);
  }
  return kept;
}

const std::vector<lines::LineSegment>& Odometry::frame_lines(const cv::Mat& image, size_t frame_index) {
  if (!detected_lines_ || detected_lines_frame_ != frame_index) {
    detected_lines_ = line_detector_.detect(image);
    detected_lines_frame_ = frame_index;
  }
  return *detected_lines_;
}

std::vector<DirectionSegment> Odometry::direction_segments(const cv::Mat& image, size_t frame_index) {
  // Detected afresh in every frame: line flow loses most lines in noisy dim images (its
  // samples fail the fit), where the rotation needs them most.
  std::vector<DirectionSegment> out;
  for (const auto& l : frame_lines(image, frame_index))
    out.push_back({camera_.normalised(l.start), camera_.normalised(l.end), l.length()});
  return out;
}

std::vector<backend::PoseDirectionObservation> Odometry::direction_observations(
    const std::vector<DirectionSegment>& segments, const Eigen::Matrix3d& R_cam_world) const {
  std::vector<backend::PoseDirectionObservation> out;
  const auto& known = directions_.directions();
  if (static_cast<int>(known.size()) < config_.directions.min_known) return out;
  const std::vector<int> dir = directions_.associate(segments, R_cam_world, camera_.focal());
  for (size_t i = 0; i < dir.size(); ++i)
    if (dir[i] >= 0) out.push_back({known[dir[i]], segments[i].start, segments[i].end});
  return out;
}

bool Odometry::plain_frame() const {
  const int below = config_.plain_scene.max_tracked_points;
  return below > 0 && count_mapped(tracks_) < below;
}

void Odometry::set_reference_lines(const std::vector<TrackedLine>& lines) {
  std::vector<lines::LineSegment> segments;
  for (const auto& l : lines) segments.push_back(l.segment);
  reference_angles_ = lines::overlap_angle_set(segments, config_.lines.overlap_angles);
}

std::optional<double> Odometry::line_angle_distance() const {
  if (!use_lines_) return std::nullopt;
  std::vector<lines::LineSegment> segments;
  for (const auto& l : line_tracks_) segments.push_back(l.segment);
  const auto current = lines::overlap_angle_set(segments, config_.lines.overlap_angles);
  const size_t min_angles = static_cast<size_t>(config_.keyframes.line_min_angles);
  if (current.size() < min_angles || reference_angles_.size() < min_angles) return std::nullopt;
  return lines::overlap_angle_distance(reference_angles_, current);
}

std::optional<double> Odometry::candidate_parallax_deg() const {
  constexpr size_t kMinCandidates = 10;
  if (rectifier_.stereo() || config_.keyframes.mono_min_candidate_parallax_deg <= 0) return std::nullopt;
  auto bearing = [&](const Eigen::Matrix3d& R_world_cam, const Eigen::Vector2d& px) {
    return (R_world_cam * camera_.normalised(px).homogeneous()).normalized().eval();
  };
  const Eigen::Matrix3d R_world_now = T_world_work_.linear();
  std::vector<double> angles;
  map_.read([&](const MapData& m) {
    for (const auto& t : tracks_) {
      if (t.point != kNoId || t.origin.keyframe == kNoId) continue;
      const auto view = m.feature_view(t.origin);
      if (!view) continue;
      const Eigen::Vector3d a = bearing(view->T_world_cam.linear(), view->px);
      const Eigen::Vector3d b = bearing(R_world_now, to_eigen(t.px));
      angles.push_back(std::atan2(a.cross(b).norm(), a.dot(b)) * 180.0 / M_PI);
    }
  });
  if (angles.size() < kMinCandidates) return std::nullopt;
  return median(angles);
}

// ---------------------------------------------------------------- failure

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

void Odometry::finish() {
  worker_.wait_idle();
  worker_.rethrow_if_failed();
  apply_keyframe_results();
}

io::Trajectory Odometry::keyframe_trajectory() const {
  io::Trajectory traj;
  map_.read([&](const MapData& m) {
    for (const auto& [id, kf] : m.keyframes) traj.push_back(kf.timestamp, to_output(kf.T_world_cam));
  });
  return traj;
}

MapData Odometry::map_snapshot() const {
  // The working camera differs from cam0 by a rotation only, and the world is defined in
  // cam0 terms already (T_world_work includes T_cam0_work), so map coordinates are output coordinates.
  return map_.read([](const MapData& m) { return m; });
}

}  // namespace pllvo::vo
