// pllvo run DATASET --out DIR: the visual odometry over a whole sequence.
#include <atomic>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>

#include "commands.h"
#include "pllvo/api/odometry.h"
#include "pllvo/io/video_source.h"
#include "pllvo/vo/run_source.h"
#include "pllvo/common/error.h"
#include "pllvo/io/sequence.h"
#include "pllvo/report/frame_annotator.h"
#include "pllvo/report/live_viewer.h"
#include "pllvo/report/report_page.h"
#include "pllvo/vo/run_sequence.h"
#include "pllvo/vo/vo_config.h"

namespace pllvo::cli {

namespace {

struct RunArgs {
  std::string dataset;
  std::string out;
  std::string config;
  std::string format = "auto";
  std::string camera;
  std::string frontend;
  bool mono = false;
  bool rgbd = false;
  bool single_thread = false;
  size_t first = 0;
  size_t max_frames = 0;
  bool report = false;
  size_t report_frames = 4;
  bool view = false;
  bool realtime = false;
  double speed = 1.0;
  std::string source;
  std::string stereo_layout = "mono";
  double stall_timeout = 5.0;
};

/// Ctrl-C and SIGTERM end a run cleanly: the flag is set by the handler (the one piece of
/// process-wide state a signal needs) and read by the run loop between frames.
std::atomic<bool>& stop_requested() {
  static std::atomic<bool> flag{false};
  return flag;
}

class StopOnSignals {
 public:
  StopOnSignals() {
    struct sigaction action {};
    action.sa_handler = [](int) { stop_requested() = true; };
    sigemptyset(&action.sa_mask);
    for (int s : {SIGINT, SIGTERM}) sigaction(s, &action, &previous_[s == SIGINT ? 0 : 1]);
  }
  ~StopOnSignals() {
    sigaction(SIGINT, &previous_[0], nullptr);
    sigaction(SIGTERM, &previous_[1], nullptr);
  }
  StopOnSignals(const StopOnSignals&) = delete;
  StopOnSignals& operator=(const StopOnSignals&) = delete;

 private:
  struct sigaction previous_[2] {};
};

void print_summary(const vo::RunSummary& s, const std::string& format, const std::string& out);

/// pllvo run --source SRC: a camera, a video file, a pipeline.
void run_source(const RunArgs& a, const vo::VoConfig& config) {
  if (a.camera.empty())
    throw InputError("--source needs --camera: the calibration (pllvo's camera YAML, a EuRoC sensor.yaml, or a "
                     "dataset folder whose calibration to use)");
  const Calibration calibration = Calibration::load(a.camera);
  io::VideoSourceOptions source_options;
  source_options.stereo_layout = a.stereo_layout;
  source_options.stall_timeout_s = a.stall_timeout;
  const auto source = io::VideoSource::open(a.source, source_options);
  vo::SourceRunOptions options;
  options.out_dir = a.out;
  options.stereo = !a.mono;
  options.realtime = a.realtime || source->live();
  options.max_frames = a.max_frames;
  options.stop = &stop_requested();
  options.progress = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };
  std::unique_ptr<report::LiveViewer> viewer;
  if (a.view) {
    viewer = std::make_unique<report::LiveViewer>();
    options.on_frame = [&](const vo::TrackingView& view) { (*viewer)(view); };
  }
  const StopOnSignals signals;
  const vo::SourceRunResult r = vo::run_source(*source, calibration.internal(), config, options);
  print_summary(r.summary, "video", a.out);
  std::printf("ended by: %s%s%s\n", r.ended_by.c_str(), r.message.empty() ? "" : ": ", r.message.c_str());
  if (a.report) std::printf("report: %s\n", report::write_report(a.out).string().c_str());
  if (r.failed()) throw InputError(r.message + " (the outputs of the frames before are written)");
}

void run(const RunArgs& a) {
  // The library API's options, so that `pllvo run` and a program using pllvo::Odometry read the
  // same configuration the same way.
  OdometryOptions odometry_options;
  odometry_options.config_yaml = a.config;
  if (!a.frontend.empty()) odometry_options.overrides.emplace_back("frontend.type", a.frontend);
  odometry_options.single_thread = a.single_thread;
  const vo::VoConfig config = vo_config_of(odometry_options);
  if (!a.source.empty() && !a.dataset.empty()) throw InputError("give a dataset folder or --source, not both");
  if (a.source.empty() && a.dataset.empty()) throw InputError("give a dataset folder, or --source with --camera");
  if (!a.source.empty()) return run_source(a, config);

  io::SequenceOptions options;
  options.format = a.format;
  options.camera_yaml = a.camera;
  options.mono = a.mono;
  options.depth = !a.mono;
  const auto sequence = io::open_sequence(a.dataset, options);

  vo::RunOptions run_options;
  run_options.out_dir = a.out;
  run_options.choose_sensors(*sequence, a.mono, a.rgbd);
  run_options.first_frame = a.first;
  run_options.max_frames = a.max_frames;
  run_options.realtime = a.realtime;
  run_options.speed = a.speed;
  run_options.progress = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };
  // Only built when asked for: a headless run never opens a window.
  std::unique_ptr<report::LiveViewer> viewer;
  if (a.view) viewer = std::make_unique<report::LiveViewer>();
  const size_t last = a.max_frames ? std::min(sequence->size(), a.first + a.max_frames) : sequence->size();
  report::FrameSnapshots snapshots(std::filesystem::path(a.out) / "frames", a.first,
                                   last > a.first ? last - a.first : 0, a.report ? a.report_frames : 0);
  if (a.view || a.report)
    run_options.on_frame = [&](const vo::TrackingView& view) {
      if (viewer) (*viewer)(view);
      snapshots(view);
    };
  const auto s = vo::run_sequence(*sequence, config, run_options);
  print_summary(s, sequence->format(), a.out);
  if (a.report) std::printf("report: %s\n", report::write_report(a.out).string().c_str());
}

void print_summary(const vo::RunSummary& s, const std::string& format, const std::string& out) {
  std::printf("%s, %s, %s front end: %zu frames in %.2f s (%.1f frames/s)\n", format.c_str(),
              s.mode(), s.stats["frontend"].get<std::string>().c_str(), s.frames, s.wall_seconds,
              s.frames_per_second);
  std::printf("tracked %zu of %zu frames, %zu keyframes, %d re-initialisations, %zu lost intervals\n",
              s.tracked_frames, s.frames, s.keyframes, s.resets, s.lost.size());
  for (const auto& l : s.lost)
    std::printf("  not tracked: frames %zu-%zu (t %.3f-%.3f s)\n", l.first_frame, l.last_frame, l.first_time,
                l.last_time);
  if (s.live) {
    const auto& rt = s.stats["realtime"];
    std::printf("realtime at %.2fx: %zu of %zu frames dropped (%.1f %%), latency mean %.0f ms, p95 %.0f ms, max %.0f ms, "
                "%lld keyframes requested while the worker was busy\n",
                s.live->speed, s.live->dropped_frames.size(), s.frames,
                s.frames ? 100.0 * s.live->dropped_frames.size() / s.frames : 0.0, 1e3 * s.live->latency_s.mean,
                1e3 * s.live->latency_s.p95, 1e3 * s.live->latency_s.max,
                rt["keyframes_requested_while_busy"].get<long long>());
    if (rt.value("keyframe_return_frames_mean", nlohmann::json()).is_number())
      std::printf("keyframes came back %.1f frames (%.0f ms) after their request on average\n",
                  rt["keyframe_return_frames_mean"].get<double>(), rt["keyframe_return_ms_mean"].get<double>());
  }
  std::printf("estimated path %.3f, largest distance from the start %.4f (%s)\n", s.path_length,
              s.max_displacement, s.metric() ? "metres" : "map units");
  if (s.error) {
    std::string how = s.error->align + " alignment";
    if (s.error->align == "sim3") how += ", scale " + std::to_string(s.error->scale);
    if (s.error->collinear_reference) how += ", straight-line ground truth";
    std::printf("ATE RMSE %.4f m over %zu poses (%s), %.2f%% of the %.3f m path\n", s.error->rmse_m,
                s.error->matched_poses, how.c_str(), s.error->percent_of_path, s.error->path_length_m);
  }
  if (s.anchored_error)
    std::printf("ATE RMSE %.4f m, %.2f%% of the path, with every frame on its keyframe's final pose (trajectory_anchored.tum)\n",
                s.anchored_error->rmse_m, s.anchored_error->percent_of_path);
  std::printf("outputs: %s/{trajectory.tum, trajectory_anchored.tum, keyframes.tum, stats.json, map.ply}\n", out.c_str());
}

}  // namespace

void add_run_command(CLI::App& app) {
  auto args = std::make_shared<RunArgs>();
  auto* cmd = app.add_subcommand("run", "visual odometry over a dataset: trajectory, keyframes, map and stats");
  cmd->add_option("dataset", args->dataset,
                  "dataset folder (EuRoC ASL, TUM RGB-D, KITTI odometry, image folder); or --source");
  cmd->add_option("--out", args->out, "output folder (created)")->required();
  cmd->add_option("--config", args->config, "VO config YAML (defaults: config/vo.yaml documents them)");
  cmd->add_option("--format", args->format, "dataset format")
      ->check(CLI::IsMember({"auto", "euroc", "tum", "kitti", "folder"}));
  cmd->add_option("--camera", args->camera, "camera YAML for TUM / image folders (default: camera.yaml inside); with "
                  "--source: the calibration (camera YAML, EuRoC sensor.yaml or a dataset folder)");
  cmd->add_flag("--mono", args->mono, "use the left camera only, also on stereo and RGB-D datasets");
  cmd->add_flag("--rgbd", args->rgbd,
                "use the left camera and its depth images, also on a stereo dataset that has them (a dataset "
                "with depth and no second camera runs RGB-D without it)")
      ->excludes("--mono");
  cmd->add_option("--frontend", args->frontend, "point front end (overrides the config)")
      ->check(CLI::IsMember({"auto", "superpoint", "orb", "shitomasi"}));
  cmd->add_flag("--single-thread", args->single_thread,
                "process keyframes inline (deterministic; slower)");
  cmd->add_option("--first", args->first, "first frame index");
  cmd->add_option("--max-frames", args->max_frames, "process at most this many frames (0: all)");
  cmd->add_flag("--report", args->report, "also write DIR/report.html (plots, timing, annotated frames)");
  cmd->add_option("--report-frames", args->report_frames, "annotated frames in the report (default 4)");
  cmd->add_flag("--realtime", args->realtime,
                "live-rate playback: frames arrive at their timestamps, the tracker never waits for the keyframe "
                "worker, frames that arrive while it is busy are dropped (counted in stats.json)");
  cmd->add_option("--speed", args->speed, "playback speed factor for --realtime (default 1)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--source", args->source,
                  "a live or recorded video source instead of a dataset: a video file, a camera (index or "
                  "/dev/videoN), a GStreamer pipeline or an image pattern; needs --camera. Cameras run at live "
                  "rate (--realtime), files as fast as tracking goes unless --realtime is given");
  cmd->add_option("--stereo-layout", args->stereo_layout, "--source: mono, or side-by-side (left | right in one frame)")
      ->check(CLI::IsMember({"mono", "side-by-side"}));
  cmd->add_option("--stall-timeout", args->stall_timeout, "--source: seconds without a frame before the source counts "
                  "as stalled (default 5)")->check(CLI::PositiveNumber);
  cmd->add_flag("--view", args->view, "live window with the tracked points and lines (needs a display)");
  cmd->callback([args] { run(*args); });
}

}  // namespace pllvo::cli
