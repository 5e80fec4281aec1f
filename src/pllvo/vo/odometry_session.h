#pragma once
// One run of the odometry from its first frame to its outputs, whatever feeds it: a dataset
// (`pllvo run`), a caller's frames (the library API, pllvo::Odometry) or a live source. It checks
// every frame before the odometry sees it, keeps the run's statistics, optionally takes frames
// from a camera thread through a one-frame queue (the live-rate logic: the tracker never waits
// for the keyframe worker, a frame that arrives while the previous one still waits is dropped),
// and writes the files that `pllvo run --out DIR` writes.
#include <chrono>
#include <exception>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "pllvo/io/sequence.h"
#include "pllvo/vo/frame_slot.h"
#include "pllvo/vo/live_playback.h"
#include "pllvo/vo/odometry.h"
#include "pllvo/vo/run_output.h"
#include "pllvo/vo/run_stats.h"
#include "pllvo/vo/trajectory_error.h"
#include "pllvo/vo/vo_config.h"

namespace pllvo::vo {

struct SessionOptions {
  bool stereo = true;  ///< use cam1 when the calibration has one
  /// Else use the frames' depth images (io::Frame::depth) when the calibration has depth (RGB-D).
  bool depth = true;
  /// Live input: the tracker never waits for the keyframe worker (run.wait_when_starving is
  /// forced off), as a camera does not wait for it.
  bool live = false;
};

/// Live-rate measurements (RunSummary::live, stats.json "realtime").
struct LiveRunStats {
  double speed = 1.0;
  std::vector<size_t> dropped_frames;
  LatencySummary latency_s;  ///< arrival to pose, seconds
};

/// Where the frames came from: stats.json names it, and the ground truth gives the error.
struct SessionSource {
  std::string root;
  std::string format = "api";
  std::optional<io::Trajectory> ground_truth;
};

struct RunSummary {
  size_t frames = 0;
  size_t tracked_frames = 0;
  size_t keyframes = 0;
  int resets = 0;
  double wall_seconds = 0;
  double frames_per_second = 0;
  bool stereo = false;
  bool depth = false;  ///< RGB-D
  bool metric() const { return stereo || depth; }  ///< a map at metric scale
  const char* mode() const { return stereo ? "stereo" : depth ? "rgbd" : "mono"; }
  std::vector<LostInterval> lost;
  io::Trajectory trajectory;  ///< tracked frames, T_world_cam0, each as it was tracked
  /// The same frames on their keyframes' final poses (keyframe_anchored_trajectory).
  io::Trajectory anchored_trajectory;
  io::Trajectory keyframe_trajectory;
  MapData map;
  double path_length = 0;      ///< of the estimated trajectory (map units; metres for stereo)
  double max_displacement = 0; ///< largest distance from the first tracked pose
  nlohmann::json stats;       ///< what stats.json holds
  std::optional<TrajectoryError> error;  ///< of `trajectory`, when the source has ground truth
  std::optional<TrajectoryError> anchored_error;  ///< of `anchored_trajectory`
  std::optional<LiveRunStats> live;      ///< live-rate runs
};

class OdometrySession {
 public:
  OdometrySession(const VoConfig& config, const io::Calibration& calibration, const SessionOptions& options = {});
  /// Stops the live thread (frames still queued are not processed) and waits for the worker.
  ~OdometrySession();
  OdometrySession(const OdometrySession&) = delete;
  OdometrySession& operator=(const OdometrySession&) = delete;

  /// Checks the frame (check_frame) and processes it on the caller's thread. A bad frame is an
  /// InputError and leaves the odometry as it was: the next good frame is tracked as usual.
  FrameRecord process(io::Frame frame);
  /// Live input, returns at once: hands the frame (checked first, as by process) to the tracking
  /// thread, which is started on the first call. A frame still waiting there is replaced and
  /// counted as dropped; its index is returned.
  std::optional<size_t> push(io::Frame frame);
  /// Called after every processed frame, on the thread that processed it (with push: the
  /// tracking thread), with the odometry's lock held: keep it short.
  void set_on_frame(std::function<void(const FrameRecord&, const TrackingView&)> on_frame);
  /// Closes live input (waiting for the frame in the queue), waits for pending keyframes and
  /// stops the clock. Rethrows an error that stopped the tracking thread. Idempotent.
  void finish();

  /// Everything `pllvo run` reports; call after finish(). `replayed`: the live-rate measurements
  /// of a recorded sequence replayed at its rate (LivePlayback), in place of push()'s own.
  RunSummary summary(const SessionSource& source, const std::optional<LiveRunStats>& replayed = std::nullopt) const;
  /// trajectory.tum, keyframes.tum, map.ply and stats.json in `dir` (created); each file is
  /// written whole or not at all.
  static void save(const RunSummary& summary, const std::filesystem::path& dir);

  bool stereo() const { return odometry_->stereo(); }
  bool depth() const { return odometry_->depth(); }  ///< RGB-D
  const RunStats& stats() const { return stats_; }
  RunStats& stats() { return stats_; }  ///< thread-safe: a caller may add its own timings
  /// The odometry, for read access between frames; not while live input runs.
  const Odometry& odometry() const { return *odometry_; }
  /// Frames processed so far (any thread).
  size_t frames_processed() const;
  std::vector<size_t> dropped_frames() const;
  bool live_used() const;  ///< push() was called

 private:
  /// Converts a colour frame to gray (BGR, as OpenCV reads it) and checks it: an image of the
  /// calibration's size, 8-bit, a right image when stereo, a finite timestamp later than the
  /// previous accepted frame's. InputError naming the frame otherwise; accepted, its timestamp
  /// becomes the previous one.
  void accept(io::Frame& frame);
  FrameRecord process_accepted(io::Frame& frame);
  void live_loop();

  VoConfig config_;
  io::Calibration calibration_;
  RunStats stats_;
  int previous_opencv_threads_ = -1;  ///< restored by the destructor (single-thread runs only)
  std::unique_ptr<Odometry> odometry_;
  std::function<void(const FrameRecord&, const TrackingView&)> on_frame_;

  mutable std::mutex odometry_mutex_;  ///< the odometry and what process_accepted updates
  size_t processed_ = 0;
  std::optional<std::chrono::steady_clock::time_point> first_frame_time_;
  double wall_seconds_ = 0;
  std::vector<double> latency_s_;  ///< live input: arrival to pose, per processed frame

  /// Input state: taken briefly by push(), so a camera thread never waits for tracking.
  mutable std::mutex input_mutex_;
  std::optional<double> last_timestamp_;  ///< of the last accepted frame
  bool finished_ = false;
  std::vector<size_t> dropped_;
  bool live_used_ = false;  ///< push() was called
  std::exception_ptr live_failure_;

  FrameSlot slot_;
  std::thread live_thread_;
};

/// A progress line for a long run, every `interval_s` of wall time (0: never):
/// "frame 120/500  9.8 fps  tracked 118  keyframes 14  resets 0" (no "/500" when the total is unknown).
class ProgressReport {
 public:
  ProgressReport(double interval_s, std::function<void(const std::string&)> callback);
  /// After each frame given to `session`: `done` frames so far, of `total` (0: unknown).
  void after_frame(const OdometrySession& session, size_t done, size_t total);

 private:
  double interval_s_;
  std::function<void(const std::string&)> callback_;
  std::chrono::steady_clock::time_point start_, last_;
};

}  // namespace pllvo::vo
