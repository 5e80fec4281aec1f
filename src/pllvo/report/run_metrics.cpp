#include "pllvo/report/run_metrics.h"

#include <cmath>

#include <spdlog/spdlog.h>

#include "pllvo/eval/evaluator.h"
#include "pllvo/vo/trajectory_error.h"

namespace pllvo::report {
namespace {

double number(const nlohmann::json& j, const char* key) {
  return j.contains(key) && j[key].is_number() ? j[key].get<double>() : NAN;
}

}  // namespace

const std::vector<ModuleTimer>& module_timers() {
  static const std::vector<ModuleTimer> timers = {
      {"point_extraction", {"kf_detect"}},
      {"line_extraction", {"kf_lines"}},
      {"tracking", {"klt", "line_tracking"}},
      {"matching", {"kf_match"}},
      {"ba", {"kf_ba"}},
  };
  return timers;
}

std::map<std::string, double> RunMetrics::values() const {
  std::map<std::string, double> v = {
      {"frames", frames},
      {"tracked_frames", tracked_frames},
      {"tracked_share", tracked_share},
      {"keyframes", keyframes},
      {"resets", resets},
      {"ate_rmse_m", ate_rmse_m},
      {"ate_percent", ate_percent},
      {"ate_anchored_percent", ate_anchored_percent},
      {"rpe_trans_m", rpe_trans_m},
      {"rpe_rot_deg", rpe_rot_deg},
      {"frame_ms_mean", frame_ms_mean},
      {"frame_ms_median", frame_ms_median},
      {"frame_ms_p95", frame_ms_p95},
      {"wall_ms_per_frame", wall_ms_per_frame},
      {"cpu_ms_per_frame", cpu_ms_per_frame},
      {"matcher_layers_mean", matcher_layers_mean},
      {"matcher_pruned_share", matcher_pruned_share},
      {"dropped_share", dropped_share},
      {"latency_mean_ms", latency_mean_ms},
      {"latency_p95_ms", latency_p95_ms},
      {"keyframe_return_frames", keyframe_return_frames},
  };
  for (const auto& t : module_timers()) {
    const auto it = module_ms.find(t.column);
    v["ms_" + t.column] = it == module_ms.end() ? NAN : it->second;
  }
  return v;
}

void add_trajectory_errors(const io::Trajectory& estimate, const io::Trajectory& reference, bool metric_scale,
                           size_t rpe_delta_frames, RunMetrics& m) {
  if (estimate.size() < 3 || reference.size() < 3 || !reference.has_stamps()) return;
  // The APE as `pllvo run` reports it, a straight-line reference (evo refuses it) included.
  const auto ate = vo::trajectory_error(estimate, reference, metric_scale);
  if (!ate) return;
  m.ate_rmse_m = ate->rmse_m;
  m.ate_percent = ate->path_length_m > 0 ? ate->percent_of_path : NAN;
  eval::EvalOptions options;
  options.align = metric_scale ? eval::AlignMode::se3 : eval::AlignMode::sim3;
  options.allow_collinear = ate->collinear_reference;
  options.rpe.delta = static_cast<double>(std::max<size_t>(1, rpe_delta_frames));
  try {
    const eval::Evaluator evaluator(options);
    const auto prepared = evaluator.prepare(reference, estimate);
    if (prepared.ref.size() > options.rpe.delta) {
      m.rpe_trans_m = evaluator.rpe(prepared, eval::PoseRelation::trans_part).stats.rmse;
      m.rpe_rot_deg = evaluator.rpe(prepared, eval::PoseRelation::angle_deg).stats.rmse;
    }
  } catch (const std::exception& e) {
    // Too few matched poses or a degenerate alignment: the run has no error figure.
    spdlog::warn("trajectory error not computed: {}", e.what());
  }
}

void add_stats(const nlohmann::json& stats, RunMetrics& m) {
  if (stats.contains("matcher") && stats["matcher"].is_string()) m.matcher = stats["matcher"].get<std::string>();
  m.frames = number(stats, "frames");
  m.tracked_frames = number(stats, "tracked_frames");
  m.keyframes = number(stats, "keyframes");
  m.resets = number(stats, "resets");
  m.tracked_share = m.frames > 0 ? m.tracked_frames / m.frames : NAN;
  if (stats.contains("trajectory_error_keyframe_anchored"))
    m.ate_anchored_percent = number(stats["trajectory_error_keyframe_anchored"], "ate_percent_of_path");
  const double wall = number(stats, "wall_time_s");
  m.wall_ms_per_frame = m.frames > 0 ? 1000.0 * wall / m.frames : NAN;
  const nlohmann::json timing = stats.value("timing_ms", nlohmann::json::object());
  if (timing.contains("frame")) {
    m.frame_ms_mean = number(timing["frame"], "mean");
    m.frame_ms_median = number(timing["frame"], "median");
    m.frame_ms_p95 = number(timing["frame"], "p95");
  }
  const nlohmann::json samples = stats.value("per_frame", nlohmann::json::object());
  if (samples.contains("matcher_layers_run")) m.matcher_layers_mean = number(samples["matcher_layers_run"], "mean");
  if (samples.contains("matcher_pruned_share")) m.matcher_pruned_share = number(samples["matcher_pruned_share"], "mean");
  if (stats.contains("realtime")) {
    const auto& live = stats["realtime"];
    m.dropped_share = m.frames > 0 ? number(live, "frames_dropped") / m.frames : NAN;
    m.latency_mean_ms = number(live, "latency_mean_ms");
    m.latency_p95_ms = number(live, "latency_p95_ms");
    m.keyframe_return_frames = number(live, "keyframe_return_frames_mean");
  }
  for (const auto& t : module_timers()) {
    double sum = 0;
    bool any = false;
    for (const auto& name : t.timers)
      if (timing.contains(name)) sum += number(timing[name], "mean"), any = true;
    m.module_ms[t.column] = any ? sum : 0.0;  // a module that never ran took no time
  }
}

}  // namespace pllvo::report
