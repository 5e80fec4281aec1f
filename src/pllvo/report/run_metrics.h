#pragma once
// The numbers `pllvo bench` compares for one run: accuracy against ground truth (ATE, RPE),
// tracking (share of frames tracked, keyframes, resets) and time (per frame and per module,
// read from the run's stats.json). Missing values (no ground truth, a failed run) are NaN.
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "pllvo/io/trajectory.h"

namespace pllvo::report {

/// The per-module columns of the bench table and the stats.json timers each one sums
/// (mean ms per call; keyframe modules run once per keyframe, the others once per frame).
struct ModuleTimer {
  std::string column;               ///< point_extraction, line_extraction, tracking, matching, ba
  std::vector<std::string> timers;  ///< stats.json timing_ms keys
};
const std::vector<ModuleTimer>& module_timers();

struct RunMetrics {
  std::string error;  ///< non-empty: the run failed with this message
  std::string matcher;  ///< keyframe matcher the run used (stats.json; `auto` resolved)
  double frames = 0, tracked_frames = 0, keyframes = 0, resets = 0;
  double tracked_share = 0;  ///< tracked / frames
  double ate_rmse_m = NAN, ate_percent = NAN;  ///< APE translation RMSE; % of the ground-truth path
  /// The same of the keyframe-anchored trajectory (stats.json trajectory_error_keyframe_anchored).
  double ate_anchored_percent = NAN;
  double rpe_trans_m = NAN, rpe_rot_deg = NAN; ///< RPE RMSE over pairs ~1 s apart
  double frame_ms_mean = NAN, frame_ms_median = NAN, frame_ms_p95 = NAN;  ///< tracking thread
  double wall_ms_per_frame = NAN;  ///< whole run (worker included) / frames: throughput
  /// CPU time of the process (all threads) during the run / frames: the cost, much less
  /// disturbed than wall time by other work on a shared machine.
  double cpu_ms_per_frame = NAN;
  std::map<std::string, double> module_ms;  ///< module_timers() columns, mean ms per call
  /// LightGlue's adaptivity over the run's keyframe matches: mean layers run before the
  /// confidence exit, mean share of points pruned (NaN for matchers without it).
  double matcher_layers_mean = NAN, matcher_pruned_share = NAN;
  /// Live-rate runs (stats.json `realtime`): share of frames dropped, latency arrival to pose,
  /// frames the tracker took between a keyframe's request and its result (mean).
  double dropped_share = NAN, latency_mean_ms = NAN, latency_p95_ms = NAN, keyframe_return_frames = NAN;

  bool ok() const { return error.empty(); }
  /// Every number by name (the bench aggregates them alike).
  std::map<std::string, double> values() const;
};

/// APE (translation) and RPE (translation, rotation angle) of `estimate` against `reference`,
/// SE3 alignment when `metric_scale`, else Sim3; RPE pairs `rpe_delta_frames` estimate poses
/// apart. The APE is vo::trajectory_error's (as `pllvo run` reports it: a straight-line reference
/// is aligned too). Fields stay NaN when fewer than 3 poses match or the alignment is degenerate.
void add_trajectory_errors(const io::Trajectory& estimate, const io::Trajectory& reference, bool metric_scale,
                           size_t rpe_delta_frames, RunMetrics& m);

/// Counts and timing from a run's stats.json (the object `pllvo run` writes).
void add_stats(const nlohmann::json& stats, RunMetrics& m);

}  // namespace pllvo::report
