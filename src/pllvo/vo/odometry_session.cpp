#include "pllvo/vo/odometry_session.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>

#include "pllvo/common/error.h"

namespace pllvo::vo {
namespace {

using Clock = std::chrono::steady_clock;

nlohmann::json lost_json(const std::vector<LostInterval>& lost) {
  nlohmann::json j = nlohmann::json::array();
  for (const auto& l : lost)
    j.push_back({{"first_frame", l.first_frame},
                 {"last_frame", l.last_frame},
                 {"frames", l.last_frame - l.first_frame + 1},
                 {"first_time", l.first_time},
                 {"last_time", l.last_time}});
  return j;
}

std::string frame_name(const io::Frame& frame) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "frame %zu (t %.6f s)", frame.index, frame.timestamp);
  return buf;
}

/// 8-bit gray of `image` (BGR / BGRA converted); InputError for other types.
cv::Mat to_gray(const cv::Mat& image, const io::Frame& frame, const char* which) {
  if (image.depth() != CV_8U)
    throw InputError(frame_name(frame) + ": the " + which + " image must be 8-bit (gray, BGR or BGRA); got depth " +
                     std::to_string(image.depth()) + " with " + std::to_string(image.channels()) + " channels");
  cv::Mat gray;
  switch (image.channels()) {
    case 1:
      return image;
    case 3:
      cv::cvtColor(image, gray, cv::COLOR_BGR2GRAY);
      return gray;
    case 4:
      cv::cvtColor(image, gray, cv::COLOR_BGRA2GRAY);
      return gray;
    default:
      throw InputError(frame_name(frame) + ": the " + which + " image has " + std::to_string(image.channels()) +
                       " channels (1, 3 or 4 expected)");
  }
}

void check_size(const cv::Mat& image, const camera::CameraModel& camera, const io::Frame& frame, const char* which) {
  if (image.cols != camera.width() || image.rows != camera.height())
    throw InputError(frame_name(frame) + ": the " + which + " image is " + std::to_string(image.cols) + "x" +
                     std::to_string(image.rows) + ", the calibration's camera is " + std::to_string(camera.width()) +
                     "x" + std::to_string(camera.height()));
}

}  // namespace

OdometrySession::OdometrySession(const VoConfig& config, const io::Calibration& calibration,
                                 const SessionOptions& options)
    : config_(config), calibration_(calibration) {
  if (!calibration_.cam0) throw InputError("the calibration has no camera");
  // A live camera does not wait: the tracker must never block on the keyframe worker.
  if (options.live) config_.run.wait_when_starving = false;
  // Single-thread runs are for repeatable results, and OpenCV's own worker threads made two runs
  // of the same binary differ (measured: ORB stereo, 80 frames, first difference at frame 49
  // with OpenCV's threads, none without; docs/vo.md).
  if (!config_.run.threaded) {
    previous_opencv_threads_ = cv::getNumThreads();
    cv::setNumThreads(1);
  }
  odometry_ = std::make_unique<Odometry>(config_, calibration_, options.stereo && calibration_.stereo(),
                                         options.depth && calibration_.has_depth(), stats_);
}

OdometrySession::~OdometrySession() {
  slot_.close();
  {
    std::lock_guard<std::mutex> lock(input_mutex_);
    finished_ = true;
  }
  if (live_thread_.joinable()) live_thread_.join();
  odometry_.reset();  // joins the keyframe worker
  if (previous_opencv_threads_ >= 0) cv::setNumThreads(previous_opencv_threads_);
}

void OdometrySession::accept(io::Frame& frame) {
  const camera::CameraModel& cam0 = *calibration_.cam0;
  if (!std::isfinite(frame.timestamp)) throw InputError(frame_name(frame) + ": the timestamp is not a finite number");
  if (frame.left.empty()) throw InputError(frame_name(frame) + ": the left image is empty");
  frame.left = to_gray(frame.left, frame, "left");
  check_size(frame.left, cam0, frame, "left");
  if (odometry_->stereo()) {
    if (frame.right.empty())
      throw InputError(frame_name(frame) + ": a stereo odometry needs a right image (or build it monocular)");
    frame.right = to_gray(frame.right, frame, "right");
    check_size(frame.right, *calibration_.cam1, frame, "right");
  } else {
    frame.right.release();  // a monocular run ignores a second image
  }
  if (odometry_->depth() && !frame.depth.empty()) {
    if (frame.depth.type() != CV_32FC1)
      throw InputError(frame_name(frame) + ": the depth image must be CV_32FC1, metres");
    check_size(frame.depth, cam0, frame, "depth");
  } else if (!odometry_->depth()) {
    frame.depth.release();
  }
  std::lock_guard<std::mutex> lock(input_mutex_);
  if (finished_) throw InputError(frame_name(frame) + ": the odometry has finished; it takes no more frames");
  if (last_timestamp_ && !(frame.timestamp > *last_timestamp_)) {
    char buf[160];
    std::snprintf(buf, sizeof buf, ": timestamps must increase (the previous frame's is %.6f s)", *last_timestamp_);
    throw InputError(frame_name(frame) + buf);
  }
  last_timestamp_ = frame.timestamp;
}

FrameRecord OdometrySession::process_accepted(io::Frame& frame) {
  std::lock_guard<std::mutex> lock(odometry_mutex_);
  if (!first_frame_time_) first_frame_time_ = Clock::now();
  FrameRecord record = odometry_->process(frame);
  ++processed_;
  if (on_frame_) on_frame_(record, odometry_->tracking_view());
  return record;
}

FrameRecord OdometrySession::process(io::Frame frame) {
  if (live_used()) throw InputError(frame_name(frame) + ": process() after push(): a session takes frames one way");
  accept(frame);
  return process_accepted(frame);
}

std::optional<size_t> OdometrySession::push(io::Frame frame) {
  const auto arrival = Clock::now();
  {
    std::lock_guard<std::mutex> lock(input_mutex_);
    if (live_failure_) std::rethrow_exception(live_failure_);
  }
  accept(frame);
  {
    std::lock_guard<std::mutex> lock(input_mutex_);
    live_used_ = true;
    if (!live_thread_.joinable()) live_thread_ = std::thread([this] { live_loop(); });
  }
  const auto replaced = slot_.put(std::move(frame), arrival);
  if (replaced) {
    std::lock_guard<std::mutex> lock(input_mutex_);
    dropped_.push_back(*replaced);
  }
  return replaced;
}

void OdometrySession::live_loop() {
  try {
    while (auto item = slot_.take()) {
      process_accepted(item->frame);
      std::lock_guard<std::mutex> lock(odometry_mutex_);
      latency_s_.push_back(std::chrono::duration<double>(Clock::now() - item->arrival).count());
    }
  } catch (...) {
    std::lock_guard<std::mutex> lock(input_mutex_);
    live_failure_ = std::current_exception();
    finished_ = true;
  }
}

void OdometrySession::set_on_frame(std::function<void(const FrameRecord&, const TrackingView&)> on_frame) {
  std::lock_guard<std::mutex> lock(odometry_mutex_);
  on_frame_ = std::move(on_frame);
}

void OdometrySession::finish() {
  slot_.close();
  if (live_thread_.joinable()) live_thread_.join();
  {
    std::lock_guard<std::mutex> lock(input_mutex_);
    finished_ = true;
    if (live_failure_) std::rethrow_exception(live_failure_);
  }
  std::lock_guard<std::mutex> lock(odometry_mutex_);
  if (wall_seconds_ > 0 || !first_frame_time_) return;
  odometry_->finish();
  wall_seconds_ = std::chrono::duration<double>(Clock::now() - *first_frame_time_).count();
}

size_t OdometrySession::frames_processed() const {
  std::lock_guard<std::mutex> lock(odometry_mutex_);
  return processed_;
}

bool OdometrySession::live_used() const {
  std::lock_guard<std::mutex> lock(input_mutex_);
  return live_used_;
}

std::vector<size_t> OdometrySession::dropped_frames() const {
  std::lock_guard<std::mutex> lock(input_mutex_);
  std::vector<size_t> d = dropped_;
  std::sort(d.begin(), d.end());
  return d;
}

RunSummary OdometrySession::summary(const SessionSource& source, const std::optional<LiveRunStats>& replayed) const {
  std::lock_guard<std::mutex> lock(odometry_mutex_);
  const Odometry& odometry = *odometry_;
  RunSummary summary;
  summary.stereo = odometry.stereo();
  summary.depth = odometry.depth();
  summary.resets = odometry.resets();
  summary.wall_seconds = wall_seconds_;
  summary.lost = lost_intervals(odometry.records());
  summary.trajectory = tracked_trajectory(odometry.records());
  summary.tracked_frames = summary.trajectory.size();
  for (size_t i = 0; i < summary.trajectory.size(); ++i) {
    const auto& p = summary.trajectory.poses[i].translation();
    if (i > 0) summary.path_length += (p - summary.trajectory.poses[i - 1].translation()).norm();
    summary.max_displacement =
        std::max(summary.max_displacement, (p - summary.trajectory.poses[0].translation()).norm());
  }
  // One read of the keyframes for both: the worker may still move them between two reads.
  const std::vector<KeyframePose> keyframes = odometry.keyframe_poses();
  summary.anchored_trajectory = keyframe_anchored_trajectory(odometry.records(), keyframes);
  summary.keyframe_trajectory = keyframe_trajectory(keyframes);
  summary.keyframes = summary.keyframe_trajectory.size();
  summary.map = odometry.map_snapshot();
  if (replayed) {
    summary.live = replayed;
  } else if (live_used()) {
    summary.live.emplace();
    summary.live->dropped_frames = dropped_frames();
    summary.live->latency_s = summarize_latency(latency_s_);
  }
  summary.frames = odometry.records().size() + (summary.live ? summary.live->dropped_frames.size() : 0);
  summary.frames_per_second = wall_seconds_ > 0 ? summary.frames / wall_seconds_ : 0;

  nlohmann::json j = stats_.to_json();
  j["sequence"] = source.root;
  j["format"] = source.format;
  j["mode"] = summary.mode();
  j["frontend"] = odometry.frontend_name();
  j["matcher"] = odometry.matcher_name();
  j["pipeline"] = {{"lines", config_.for_mode(summary.metric()).pipeline.lines},
                   {"line_tracking", config_.pipeline.line_tracking},
                   {"cross_constraint", config_.lines.cross_constraint.enabled},
                   {"line_keyframe_trigger", config_.keyframes.use_line_trigger}};
  j["threaded"] = config_.run.threaded;
  j["frames"] = summary.frames;
  j["tracked_frames"] = summary.tracked_frames;
  j["keyframes"] = summary.keyframes;
  nlohmann::json by_reason = nlohmann::json::object();
  for (KeyframeReason r : all_keyframe_reasons()) by_reason[to_string(r)] = stats_.count("keyframes." + to_string(r));
  j["keyframes_by_reason"] = by_reason;
  j["resets"] = summary.resets;
  j["lost_intervals"] = lost_json(summary.lost);
  j["map"] = {{"points", summary.map.points.size()},
              {"lines", summary.map.lines.size()},
              {"keyframes", summary.map.keyframes.size()}};
  j["estimate"] = {{"path_length", summary.path_length}, {"max_displacement", summary.max_displacement}};
  j["wall_time_s"] = summary.wall_seconds;
  j["frames_per_second"] = summary.frames_per_second;
  if (source.ground_truth) {
    summary.error = trajectory_error(summary.trajectory, *source.ground_truth, summary.metric());
    summary.anchored_error = trajectory_error(summary.anchored_trajectory, *source.ground_truth, summary.metric());
  }
  auto error_json = [](const TrajectoryError& e) {
    return nlohmann::json{{"align", e.align},          {"matched_poses", e.matched_poses},
                          {"ate_rmse_m", e.rmse_m},     {"ate_max_m", e.max_m},
                          {"path_length_m", e.path_length_m}, {"ate_percent_of_path", e.percent_of_path},
                          {"scale", e.scale}, {"collinear_reference", e.collinear_reference}};
  };
  if (summary.error) j["trajectory_error"] = error_json(*summary.error);
  if (summary.anchored_error) j["trajectory_error_keyframe_anchored"] = error_json(*summary.anchored_error);
  if (summary.live) {
    const auto& live = *summary.live;
    j["realtime"] = {{"speed", live.speed},
                     {"frames_dropped", live.dropped_frames.size()},
                     {"dropped_frames", live.dropped_frames},
                     {"latency_mean_ms", 1e3 * live.latency_s.mean},
                     {"latency_p95_ms", 1e3 * live.latency_s.p95},
                     {"latency_max_ms", 1e3 * live.latency_s.max},
                     {"keyframes_requested_while_busy", stats_.count("keyframes_requested_while_busy")}};
    // How stale a keyframe is when the tracker takes it: its request to its result.
    for (const char* name : {"keyframe_return_frames", "keyframe_return_ms"}) {
      const auto& per_frame = j["per_frame"];
      const bool any = per_frame.contains(name) && per_frame[name].contains("mean");
      j["realtime"][std::string(name) + "_mean"] = any ? per_frame[name]["mean"] : nlohmann::json(nullptr);
    }
  }
  summary.stats = j;
  return summary;
}

void OdometrySession::save(const RunSummary& summary, const std::filesystem::path& dir) {
  write_trajectory_tum(summary.trajectory, dir / "trajectory.tum");
  write_trajectory_tum(summary.anchored_trajectory, dir / "trajectory_anchored.tum");
  write_trajectory_tum(summary.keyframe_trajectory, dir / "keyframes.tum");
  write_map_ply(summary.map, dir / "map.ply");
  write_json(summary.stats, dir / "stats.json");
}

ProgressReport::ProgressReport(double interval_s, std::function<void(const std::string&)> callback)
    : interval_s_(interval_s), callback_(std::move(callback)), start_(Clock::now()), last_(start_) {}

void ProgressReport::after_frame(const OdometrySession& session, size_t done, size_t total) {
  if (!callback_ || interval_s_ <= 0) return;
  const auto now = Clock::now();
  if (std::chrono::duration<double>(now - last_).count() < interval_s_) return;
  last_ = now;
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const std::string of = total > 0 ? "/" + std::to_string(total) : "";
  char line[256];
  std::snprintf(line, sizeof line, "frame %zu%s  %.1f fps  tracked %lld  keyframes %lld  resets %d", done, of.c_str(),
                elapsed > 0 ? done / elapsed : 0.0, session.stats().count("tracked_frames"),
                session.stats().count("keyframes"), session.odometry().resets());
  callback_(line);
}

}  // namespace pllvo::vo
