#include "pllvo/vo/run_sequence.h"

#include <chrono>
#include <cstdio>

#include <opencv2/core/utility.hpp>
#include <spdlog/spdlog.h>

#include "pllvo/common/error.h"
#include "pllvo/eval/eval_error.h"
#include "pllvo/eval/evaluator.h"
#include "pllvo/vo/live_playback.h"
#include "pllvo/vo/odometry.h"

namespace pllvo::vo {
namespace {

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

std::string describe(const LostInterval& l) {
  char buf[128];
  std::snprintf(buf, sizeof buf, "frames %zu-%zu (t %.3f-%.3f s)", l.first_frame, l.last_frame, l.first_time,
                l.last_time);
  return buf;
}

}  // namespace

namespace {

TrajectoryError evaluate(const io::Trajectory& estimate, const io::Trajectory& reference, bool metric_scale,
                         bool allow_collinear) {
  eval::EvalOptions options;
  options.align = metric_scale ? eval::AlignMode::se3 : eval::AlignMode::sim3;
  options.allow_collinear = allow_collinear;
  const eval::Evaluator evaluator(options);
  const auto prepared = evaluator.prepare(reference, estimate);
  const auto ape = evaluator.ape(prepared, eval::PoseRelation::trans_part);
  TrajectoryError e;
  e.align = metric_scale ? "se3" : "sim3";
  e.collinear_reference = allow_collinear;
  e.matched_poses = prepared.ref.size();
  e.rmse_m = ape.stats.rmse;
  e.max_m = ape.stats.max;
  for (size_t i = 1; i < prepared.ref.size(); ++i)
    e.path_length_m += (prepared.ref[i].translation() - prepared.ref[i - 1].translation()).norm();
  e.percent_of_path = e.path_length_m > 0 ? 100.0 * e.rmse_m / e.path_length_m : 0.0;
  if (prepared.alignment) e.scale = prepared.alignment->transform.scale;
  return e;
}

}  // namespace

std::optional<TrajectoryError> trajectory_error(const io::Trajectory& estimate, const io::Trajectory& reference,
                                                bool metric_scale) {
  if (estimate.size() < 3 || reference.size() < 3 || !reference.has_stamps()) return std::nullopt;
  try {
    try {
      return evaluate(estimate, reference, metric_scale, false);
    } catch (const eval::EvalError& ex) {
      if (ex.kind() != eval::EvalErrorKind::geometry) throw;
      // evo refuses a straight-line reference (rank-1 covariance); the least-squares fit still
      // exists, only the rotation about the line is arbitrary, which the APE does not depend on.
      auto e = evaluate(estimate, reference, metric_scale, true);
      spdlog::info("ground truth is a straight line: {} alignment with the rotation about it unobservable", e.align);
      return e;
    }
  } catch (const std::exception& ex) {
    // Too few matched stamps or a degenerate alignment: no error to report, not a failure.
    spdlog::warn("trajectory error not computed: {}", ex.what());
    return std::nullopt;
  }
}

namespace {

/// OpenCV on one thread for the run, restored after it. The single-thread mode is for
/// repeatable runs, and OpenCV's own worker threads made two runs of the same binary differ
/// (measured: ORB stereo, 80 frames, first difference at frame 49 with OpenCV's threads, none
/// without; docs/vo.md).
class OpenCvThreadsForRun {
 public:
  explicit OpenCvThreadsForRun(bool single) : previous_(cv::getNumThreads()), single_(single) {
    if (single_) cv::setNumThreads(1);
  }
  ~OpenCvThreadsForRun() {
    if (single_) cv::setNumThreads(previous_);
  }
  OpenCvThreadsForRun(const OpenCvThreadsForRun&) = delete;
  OpenCvThreadsForRun& operator=(const OpenCvThreadsForRun&) = delete;

 private:
  int previous_;
  bool single_;
};

}  // namespace

RunSummary run_sequence(const io::Sequence& sequence, const VoConfig& config, const RunOptions& options) {
  if (sequence.size() == 0) throw InputError(sequence.root(), "the sequence has no frames");
  if (options.first_frame >= sequence.size())
    throw InputError("first frame " + std::to_string(options.first_frame) + " is past the end (" +
                     std::to_string(sequence.size()) + " frames)");
  const size_t end = options.max_frames == 0 ? sequence.size()
                                             : std::min(sequence.size(), options.first_frame + options.max_frames);
  const OpenCvThreadsForRun opencv_threads(!config.run.threaded);
  VoConfig run_config = config;
  // A live camera does not wait: the tracker must never block on the keyframe worker.
  if (options.realtime) run_config.run.wait_when_starving = false;
  RunStats stats;
  const bool stereo = options.stereo && sequence.calibration().stereo();
  Odometry odometry(run_config, sequence.calibration(), stereo, stats);

  using clock = std::chrono::steady_clock;
  const auto start = clock::now();
  auto last_progress = start;
  size_t done = 0;
  const auto track = [&](io::Frame& frame) {
    odometry.process(frame);
    ++done;
    if (options.on_frame) options.on_frame(odometry.tracking_view());
    const auto now = clock::now();
    if (options.progress && config.run.progress_interval_s > 0 &&
        std::chrono::duration<double>(now - last_progress).count() >= config.run.progress_interval_s) {
      last_progress = now;
      const double elapsed = std::chrono::duration<double>(now - start).count();
      char line[256];
      std::snprintf(line, sizeof line, "frame %zu/%zu  %.1f fps  tracked %lld  keyframes %lld  resets %d",
                    frame.index + 1 - options.first_frame, end - options.first_frame, done / elapsed,
                    stats.count("tracked_frames"), stats.count("keyframes"), odometry.resets());
      options.progress(line);
    }
  };
  const auto load = [&](size_t i) {
    io::Frame frame = sequence.frame(i);
    frame.index = i;
    return frame;
  };
  std::optional<LiveRunStats> live;
  if (options.realtime) {
    LivePlaybackConfig playback_config;
    playback_config.speed = options.speed;
    const LivePlaybackResult played =
        LivePlayback(playback_config).play(options.first_frame, end, sequence.timestamps(), load, track);
    live.emplace();
    live->speed = options.speed;
    live->dropped_frames = played.dropped;
    live->latency_s = summarize_latency(played.latency_s);
  } else {
    for (size_t i = options.first_frame; i < end; ++i) {
      io::Frame frame;
      {
        ScopedTimer t(stats, "load");
        frame = load(i);
      }
      track(frame);
    }
  }
  odometry.finish();
  const double wall = std::chrono::duration<double>(clock::now() - start).count();

  RunSummary summary;
  summary.frames = end - options.first_frame;
  summary.stereo = odometry.stereo();
  summary.resets = odometry.resets();
  summary.wall_seconds = wall;
  summary.frames_per_second = wall > 0 ? summary.frames / wall : 0;
  summary.lost = lost_intervals(odometry.records());
  summary.trajectory = tracked_trajectory(odometry.records());
  summary.tracked_frames = summary.trajectory.size();
  for (size_t i = 0; i < summary.trajectory.size(); ++i) {
    const auto& p = summary.trajectory.poses[i].translation();
    if (i > 0) summary.path_length += (p - summary.trajectory.poses[i - 1].translation()).norm();
    summary.max_displacement =
        std::max(summary.max_displacement, (p - summary.trajectory.poses[0].translation()).norm());
  }
  const io::Trajectory keyframes = odometry.keyframe_trajectory();
  summary.keyframes = keyframes.size();
  const MapData map = odometry.map_snapshot();

  nlohmann::json j = stats.to_json();
  j["sequence"] = sequence.root().string();
  j["format"] = sequence.format();
  j["mode"] = summary.stereo ? "stereo" : "mono";
  j["frontend"] = odometry.frontend_name();
  j["matcher"] = odometry.matcher_name();
  j["pipeline"] = {{"lines", config.for_mode(summary.stereo).pipeline.lines},
                   {"line_tracking", config.pipeline.line_tracking},
                   {"cross_constraint", config.lines.cross_constraint.enabled},
                   {"line_keyframe_trigger", config.keyframes.use_line_trigger}};
  j["threaded"] = config.run.threaded;
  j["frames"] = summary.frames;
  j["tracked_frames"] = summary.tracked_frames;
  j["keyframes"] = summary.keyframes;
  nlohmann::json by_reason = nlohmann::json::object();
  for (KeyframeReason r : all_keyframe_reasons()) by_reason[to_string(r)] = stats.count("keyframes." + to_string(r));
  j["keyframes_by_reason"] = by_reason;
  j["resets"] = summary.resets;
  j["lost_intervals"] = lost_json(summary.lost);
  j["map"] = {{"points", map.points.size()}, {"lines", map.lines.size()}, {"keyframes", map.keyframes.size()}};
  j["estimate"] = {{"path_length", summary.path_length}, {"max_displacement", summary.max_displacement}};
  j["wall_time_s"] = wall;
  j["frames_per_second"] = summary.frames_per_second;
  if (sequence.ground_truth())
    summary.error = trajectory_error(summary.trajectory, *sequence.ground_truth(), summary.stereo);
  if (summary.error) {
    const auto& e = *summary.error;
    j["trajectory_error"] = {{"align", e.align},          {"matched_poses", e.matched_poses},
                             {"ate_rmse_m", e.rmse_m},     {"ate_max_m", e.max_m},
                             {"path_length_m", e.path_length_m}, {"ate_percent_of_path", e.percent_of_path},
                             {"scale", e.scale}, {"collinear_reference", e.collinear_reference}};
  }
  if (live) {
    j["realtime"] = {{"speed", live->speed},
                     {"frames_dropped", live->dropped_frames.size()},
                     {"dropped_frames", live->dropped_frames},
                     {"latency_mean_ms", 1e3 * live->latency_s.mean},
                     {"latency_p95_ms", 1e3 * live->latency_s.p95},
                     {"latency_max_ms", 1e3 * live->latency_s.max},
                     {"keyframes_requested_while_busy", stats.count("keyframes_requested_while_busy")}};
  }
  summary.live = live;
  summary.stats = j;

  for (const auto& l : summary.lost) spdlog::warn("not tracked: {}", describe(l));
  if (summary.live && !summary.live->dropped_frames.empty())
    spdlog::warn("dropped (arrived while the tracker was busy): {} of {} frames", summary.live->dropped_frames.size(),
                 summary.frames);

  if (!options.out_dir.empty()) {
    write_trajectory_tum(summary.trajectory, options.out_dir / "trajectory.tum");
    write_trajectory_tum(keyframes, options.out_dir / "keyframes.tum");
    write_map_ply(map, options.out_dir / "map.ply");
    write_json(j, options.out_dir / "stats.json");
  }
  return summary;
}

}  // namespace pllvo::vo
