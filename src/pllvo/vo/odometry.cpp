#include "pllvo/vo/odometry.h"

#include <algorithm>
#include <cmath>

#include <spdlog/spdlog.h>

#include "pllvo/common/error.h"

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

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

}  // namespace

Odometry::Odometry(const VoConfig& config, const io::Calibration& calibration, bool use_stereo, RunStats& stats)
    : config_(config),
      stats_(stats),
      rectifier_(calibration, use_stereo && calibration.stereo()),
      camera_(rectifier_.camera()),
      tracker_(config.klt),
      policy_(config.keyframes),
      processor_(config, camera_, rectifier_.baseline(), map_, stats),
      worker_(config.run.threaded) {
  T_work_cam0_ = rectifier_.T_cam0_work().inverse();
  // The world frame is cam0 of the first initialised frame.
  T_world_work_ = rectifier_.T_cam0_work();
}

Odometry::~Odometry() = default;

geometry::Pose Odometry::to_output(const geometry::Pose& T_world_work) const { return T_world_work * T_work_cam0_; }

FrameRecord Odometry::process(const io::Frame& frame) {
  ScopedTimer total(stats_, "frame");
  FrameRecord record;
  record.index = frame.index;
  record.timestamp = frame.timestamp;
  cv::Mat left, right;
  {
    ScopedTimer t(stats_, "rectify");
    rectifier_.apply(frame, left, right);
  }
  ImagePyramid pyramid;
  {
    ScopedTimer t(stats_, "pyramid");
    pyramid = tracker_.build_pyramid(left);
  }
  worker_.rethrow_if_failed();
  apply_keyframe_results();

  bool tracked = false;
  if (state_ == TrackingState::kTracking)
    tracked = track(frame, left, right, pyramid, record);
  else
    tracked = initialize(frame, left, right, pyramid);

  if (!pending_keyframe_frames_.empty()) {
    pyramid_buffer_.emplace_back(frame.index, pyramid);
    while (pyramid_buffer_.size() > kMaxBufferedPyramids) pyramid_buffer_.pop_front();
  }
  previous_pyramid_ = pyramid;
  previous_index_ = frame.index;

  record.tracked = tracked;
  record.segment = processor_.segment();
  if (tracked) {
    record.T_world_cam = to_output(T_world_work_);
    if (record.tracked_points == 0) record.tracked_points = count_mapped(tracks_);
  }
  stats_.add_count("frames");
  if (tracked) stats_.add_count("tracked_frames");
  stats_.add_sample("tracked_points", record.tracked_points);
  records_.push_back(record);
  return record;
}

// ---------------------------------------------------------------- initialisation

bool Odometry::initialize(const io::Frame& frame, const cv::Mat& left, const cv::Mat& right,
                          const ImagePyramid& pyramid) {
  ScopedTimer t(stats_, "init");
  return rectifier_.stereo() ? initialize_stereo(frame, left, right, pyramid)
                             : initialize_mono(frame, left, pyramid);
}

bool Odometry::initialize_stereo(const io::Frame& frame, const cv::Mat& left, const cv::Mat& right,
                                 const ImagePyramid& pyramid) {
  KeyframeJob job;
  job.frame_index = frame.index;
  job.timestamp = frame.timestamp;
  job.left = left;
  job.right = right;
  job.left_pyramid = pyramid;
  job.T_world_cam = T_world_work_;
  job.reason = KeyframeReason::kInitialization;
  job.first = true;
  const KeyframeResult result = processor_.process(job);
  if (!result.ok) return false;
  start_tracking(result, frame.timestamp);
  spdlog::info("stereo initialisation at frame {}: {} points", frame.index, result.tracks.size());
  return true;
}

void Odometry::start_mono_reference(const io::Frame& frame, const cv::Mat& left) {
  PointFeatures features = processor_.detect(left);
  if (static_cast<int>(features.size()) < config_.init.min_points) {
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
}

bool Odometry::initialize_mono(const io::Frame& frame, const cv::Mat& left, const ImagePyramid& pyramid) {
  if (!mono_ || previous_pyramid_.empty()) {
    start_mono_reference(frame, left);
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
  if (alive < config_.init.min_points || ref.frames > static_cast<size_t>(config_.init.max_frames)) {
    start_mono_reference(frame, left);
    return false;
  }
  if (median(flow) < config_.init.mono_min_flow_px) return false;

  const TwoViewInit two_view = initialize_two_view(camera_, px0, px1, config_.geometry.two_view);
  if (!two_view.ok) {
    spdlog::debug("frame {}: two-view initialisation failed ({}: {})", frame.index, two_view.model, two_view.failure);
    return false;
  }

  // World = the reference camera's frame at the current segment start pose.
  const geometry::Pose T_world_ref = T_world_work_;
  const geometry::Pose T_world_cur = T_world_ref * two_view.T_cam1_cam0.inverse();
  std::vector<std::optional<Eigen::Vector3d>> ref_points(ref.features.size());
  std::vector<cv::Point2f> second_px(ref.features.size(), cv::Point2f(NAN, NAN));
  KeyframeJob second;
  second.frame_index = frame.index;
  second.timestamp = frame.timestamp;
  second.left = left;
  second.left_pyramid = pyramid;
  second.T_world_cam = T_world_cur;
  second.reason = KeyframeReason::kInitialization;
  int made = 0;
  for (size_t k = 0, j = 0; k < which.size(); ++k) {
    const int i = which[k];
    if (!tr.ok[k]) continue;
    second_px[i] = tr.points[k];
    if (two_view.points_cam0[j]) ref_points[i] = T_world_ref * *two_view.points_cam0[j], ++made;
    ++j;
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
  spdlog::info("monocular initialisation ({}) between frames {} and {}: {} points, median parallax {:.2f} deg",
               two_view.model, reference.frame_index, frame.index, made, two_view.median_parallax_deg);
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
  has_velocity_ = false;
  velocity_ = geometry::Pose::Identity();
  lost_frames_ = 0;
  policy_.start_keyframe(timestamp, count_mapped(tracks_));
}

// ---------------------------------------------------------------- tracking

bool Odometry::track(const io::Frame& frame, const cv::Mat& left, const cv::Mat& right,
                     const ImagePyramid& pyramid, FrameRecord& record) {
  const geometry::Pose T_world_pred =
      config_.pose.use_motion_prior && has_velocity_ ? T_world_work_ * velocity_ : T_world_work_;
  const geometry::Pose T_pred_world = T_world_pred.inverse();

  std::vector<Eigen::Vector3d> positions(tracks_.size());
  std::vector<unsigned char> known(tracks_.size(), 0);
  map_.read([&](const MapData& m) {
    for (size_t i = 0; i < tracks_.size(); ++i) {
      auto it = m.points.find(tracks_[i].point);
      if (it != m.points.end()) positions[i] = it->second.position, known[i] = 1;
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
  }

  std::vector<size_t> which;
  std::vector<Eigen::Vector3d> pts;
  std::vector<Eigen::Vector2d> px;
  for (size_t i = 0; i < tracks_.size(); ++i) {
    if (!tr.ok[i] || !known[i]) continue;
    which.push_back(i);
    pts.push_back(positions[i]);
    px.push_back(to_eigen(tr.points[i]));
  }

  PoseEstimate estimate;
  {
    ScopedTimer t(stats_, "pose");
    std::optional<geometry::Pose> predicted;
    if (config_.pose.use_motion_prior && has_velocity_) predicted = T_world_pred;
    estimate = estimate_pose(camera_, pts, px, {}, predicted, config_.geometry, config_.backend);
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
  spdlog::debug("frame {}: {} map points followed, {} pose inliers, {} tracks kept", frame.index, pts.size(),
                estimate.ok ? estimate.num_point_inliers : 0, tracks_.size());

  if (!estimate.ok) {
    spdlog::debug("frame {}: pose failed ({} tracked points)", frame.index, pts.size());
    handle_lost();
    return false;
  }
  const geometry::Pose T_world_cur = estimate.T_world_cam;
  velocity_ = T_world_work_.inverse() * T_world_cur;
  // After lost frames the step spans several frames: do not extrapolate it.
  has_velocity_ = lost_frames_ == 0;
  T_world_work_ = T_world_cur;
  lost_frames_ = 0;
  record.tracked_points = estimate.num_point_inliers;
  record.tracked_lines = estimate.num_line_inliers;

  maybe_make_keyframe(frame, left, right, pyramid, estimate.num_point_inliers);
  return true;
}

void Odometry::maybe_make_keyframe(const io::Frame& frame, const cv::Mat& left, const cv::Mat& right,
                                   const ImagePyramid& pyramid, int tracked_points) {
  ScopedTimer t(stats_, "keyframe_decision");
  FrameTrackingState state;
  state.timestamp = frame.timestamp;
  state.tracked_points = tracked_points;
  state.backend_idle = worker_.idle();
  const KeyframeReason reason = policy_.decide(state);
  if (reason == KeyframeReason::kNone) return;
  if (worker_.pending() >= kMaxPendingKeyframes) {
    stats_.add_count("keyframes_deferred");
    return;
  }
  KeyframeJob job;
  job.frame_index = frame.index;
  job.timestamp = frame.timestamp;
  job.left = left;
  job.right = right;
  job.left_pyramid = pyramid;
  job.T_world_cam = T_world_work_;
  job.reason = reason;
  job.tracks = tracks_;
  policy_.start_keyframe(frame.timestamp, tracked_points);
  submit_keyframe(std::move(job));
}

void Odometry::submit_keyframe(KeyframeJob job) {
  pending_keyframe_frames_.insert(job.frame_index);
  worker_.submit([this, job = std::move(job)] {
    KeyframeResult result = processor_.process(job);
    std::lock_guard<std::mutex> lock(results_mutex_);
    results_.push_back(std::move(result));
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
    if (!result.ok || state_ != TrackingState::kTracking) continue;
    ScopedTimer t(stats_, "catch_up");
    std::vector<TrackedPoint> fresh = std::move(result.tracks);
    // Follow the keyframe's points through the frames that passed while it was processed.
    const ImagePyramid* from = nullptr;
    for (const auto& [index, pyr] : pyramid_buffer_) {
      if (index < result.frame_index) continue;
      if (index == result.frame_index) {
        from = &pyr;
        continue;
      }
      if (!from) break;
      std::vector<cv::Point2f> pts;
      for (const auto& f : fresh) pts.push_back(f.px);
      const TrackResult tr = tracker_.track(*from, pyr, pts);
      std::vector<TrackedPoint> next;
      for (size_t i = 0; i < fresh.size(); ++i)
        if (tr.ok[i]) next.push_back({tr.points[i], fresh[i].point, fresh[i].origin, fresh[i].last});
      fresh = std::move(next);
      from = &pyr;
    }
    if (!from) continue;  // the keyframe's pyramid is gone: keep the current tracks
    // Merge: the keyframe's points first, then current tracks of other map points that are
    // not too close to one of them (they keep tracking alive between keyframes).
    std::set<Id> present;
    for (const auto& f : fresh) present.insert(f.point);
    const float min_d2 = static_cast<float>(config_.frontend.min_distance_px * config_.frontend.min_distance_px) / 4;
    for (const auto& old : tracks_) {
      if (old.point == kNoId || present.count(old.point)) continue;
      bool close = false;
      for (const auto& f : fresh) {
        const cv::Point2f d = f.px - old.px;
        if (d.dot(d) < min_d2) {
          close = true;
          break;
        }
      }
      if (!close) fresh.push_back(old), present.insert(old.point);
    }
    tracks_ = std::move(fresh);
    policy_.set_reference_points(count_mapped(tracks_));
  }
  if (pending_keyframe_frames_.empty()) {
    pyramid_buffer_.clear();
  } else {
    const size_t oldest = *pending_keyframe_frames_.begin();
    while (!pyramid_buffer_.empty() && pyramid_buffer_.front().first < oldest) pyramid_buffer_.pop_front();
  }
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
  mono_.reset();
  state_ = TrackingState::kUninitialized;
  has_velocity_ = false;
  lost_frames_ = 0;
  ++resets_;
  stats_.add_count("resets");
  processor_.start_segment();
  policy_ = KeyframePolicy(config_.keyframes);
  // The new segment starts at the last tracked pose, so the trajectory stays continuous
  // (up to the unknown scale of a new monocular map).
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
