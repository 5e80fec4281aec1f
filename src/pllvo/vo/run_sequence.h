#pragma once
// `pllvo run`: a whole sequence through the odometry, with a progress line and the output
// files (trajectory.tum, keyframes.tum, stats.json, map.ply) written at the end.
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "pllvo/io/sequence.h"
#include "pllvo/vo/live_playback.h"
#include "pllvo/vo/odometry.h"
#include "pllvo/vo/run_output.h"
#include "pllvo/vo/vo_config.h"

namespace pllvo::vo {

struct RunOptions {
  std::filesystem::path out_dir;  ///< empty: write nothing
  bool stereo = true;             ///< use cam1 when the sequence has one
  size_t first_frame = 0;
  size_t max_frames = 0;  ///< 0: to the end
  /// Receives a progress line every config.run.progress_interval_s of wall time.
  std::function<void(const std::string&)> progress;
  /// Called after every frame with the tracker's view of it (live viewer, report frames).
  std::function<void(const TrackingView&)> on_frame;
  /// Live-rate playback (LivePlayback): frames arrive at their timestamps / `speed` and the
  /// tracker never waits for the keyframe worker; a frame that arrives while the previous one
  /// still waits for the tracker is dropped. Off: every frame is processed, as fast as it can be.
  bool realtime = false;
  double speed = 1.0;
};

/// Live-rate playback's measurements (RunSummary::live, stats.json "realtime").
struct LiveRunStats {
  double speed = 1.0;
  std::vector<size_t> dropped_frames;
  LatencySummary latency_s;  ///< arrival to pose, seconds
};

/// Absolute trajectory error against the sequence's ground truth (evo's APE, translation).
struct TrajectoryError {
  std::string align;        ///< "se3" (stereo, metric) or "sim3" (mono, scale unknown)
  bool collinear_reference = false;  ///< straight-line ground truth: rotation about it not observable
  size_t matched_poses = 0;
  double rmse_m = 0;
  double max_m = 0;
  double path_length_m = 0;  ///< ground truth path over the matched poses
  double percent_of_path = 0;
  double scale = 1;          ///< Sim(3) scale applied (1 for se3)
};

/// APE of `estimate` against `reference` (SE3 alignment for stereo, Sim3 for mono); nullopt
/// when fewer than 3 poses match. A straight-line reference (evo refuses it) is aligned all the
/// same, flagged `collinear_reference`.
std::optional<TrajectoryError> trajectory_error(const io::Trajectory& estimate, const io::Trajectory& reference,
                                                bool metric_scale);

struct RunSummary {
  size_t frames = 0;
  size_t tracked_frames = 0;
  size_t keyframes = 0;
  int resets = 0;
  double wall_seconds = 0;
  double frames_per_second = 0;
  bool stereo = false;
  std::vector<LostInterval> lost;
  io::Trajectory trajectory;  ///< tracked frames, T_world_cam0
  double path_length = 0;      ///< of the estimated trajectory (map units; metres for stereo)
  double max_displacement = 0; ///< largest distance from the first tracked pose
  nlohmann::json stats;       ///< what stats.json holds
  std::optional<TrajectoryError> error;  ///< when the sequence has ground truth
  std::optional<LiveRunStats> live;      ///< realtime runs
};

RunSummary run_sequence(const io::Sequence& sequence, const VoConfig& config, const RunOptions& options);

}  // namespace pllvo::vo
