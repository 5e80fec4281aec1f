#include "pllvo/vo/demo.h"

#include <chrono>
#include <cstdio>
#include <optional>
#include <random>
#include <sstream>

#include "pllvo/common/error.h"
#include "pllvo/io/sequence.h"
#include "pllvo/synth/sequence_writer.h"
#include "pllvo/synth/spec.h"
#include "pllvo/vo/superpoint_frontend.h"

namespace pllvo::vo {
namespace fs = std::filesystem;
namespace {

/// Removes a temporary folder when the demo ends, also on an exception.
class TemporaryDir {
 public:
  TemporaryDir() {
    std::random_device rd;
    path_ = fs::temp_directory_path() / ("pllvo_demo_" + std::to_string(rd()));
    fs::create_directories(path_);
  }
  ~TemporaryDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

void say(const DemoOptions& o, const std::string& line) {
  if (o.log) o.log(line);
}

/// Per-module rows of the report: {label, stats key}.
struct Module {
  const char* label;
  const char* key;
};
constexpr Module kTrackingModules[] = {
    {"image loading", "load"}, {"rectify", "rectify"}, {"pyramid", "pyramid"},   {"point tracking (KLT)", "klt"},
    {"line tracking", "line_tracking"}, {"pose", "pose"},     {"keyframe catch-up", "catch_up"},
    {"starved waits", "starved_wait"},
};
constexpr Module kKeyframeModules[] = {
    {"point extraction", "kf_detect"}, {"matching", "kf_match"},        {"stereo points", "kf_stereo"},
    {"triangulation", "kf_triangulate"}, {"lines (detect+map)", "kf_lines"}, {"bundle adjustment", "kf_ba"},
    {"keyframe total", "kf_total"},
};

}  // namespace

std::string resolve_frontend(const FrontendConfig& config, std::string* notice) {
  if (notice) notice->clear();
  if (find_superpoint_weights(config)) return "superpoint";
  if (notice)
    *notice = "no SuperPoint weights found (frontend.superpoint_weights, $PLLVO_MODELS, models/): "
              "running the ORB front end instead";
  return "orb";
}

DemoResult run_demo(const DemoOptions& options, VoConfig config) {
  DemoResult result;
  result.preset = options.preset;
  synth::SequenceSpec spec = synth::preset(options.preset);
  spec.duration_s = options.duration_s;
  spec.seed = options.seed;
  spec.camera.stereo = options.stereo;
  synth::validate(spec);

  if (options.frontend == "auto") {
    std::string notice;
    config.frontend.type = resolve_frontend(config.frontend, &notice);
    if (!notice.empty()) {
      result.notices.push_back(notice);
      say(options, "notice: " + notice);
    }
  } else {
    config.frontend.type = options.frontend;
  }
  config.validate();
  result.frontend = config.frontend.type;

  std::optional<TemporaryDir> temporary;
  fs::path root = options.out_dir;
  if (root.empty()) {
    temporary.emplace();
    root = temporary->path();
  } else {
    result.sequence_dir = root / "sequence";
    result.run_dir = root / "run";
    if (fs::exists(result.sequence_dir))
      throw InputError(result.sequence_dir, "already exists; give another --out or remove it");
    fs::create_directories(result.run_dir);
  }
  const fs::path sequence_dir = root / "sequence";

  say(options, "rendering " + options.preset + (options.stereo ? " (stereo)" : " (mono)") + ", " +
                   std::to_string(spec.num_frames()) + " frames of 752x480...");
  const auto t0 = std::chrono::steady_clock::now();
  synth::write_sequence(spec, sequence_dir);
  result.render_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  say(options, "running the odometry (" + config.frontend.type + " front end)...");
  const auto sequence = io::open_sequence(sequence_dir);
  RunOptions run;
  run.stereo = options.stereo;
  run.out_dir = result.run_dir;
  run.progress = options.log;
  result.summary = run_sequence(*sequence, config, run);
  return result;
}

std::string format_demo_report(const DemoResult& r) {
  const RunSummary& s = r.summary;
  std::ostringstream out;
  char line[256];
  std::snprintf(line, sizeof line, "sequence   %s, %zu frames, %s, rendered in %.1f s\n", r.preset.c_str(), s.frames,
                s.stereo ? "stereo" : "mono", r.render_seconds);
  out << line;
  std::snprintf(line, sizeof line, "odometry   %s front end, %s matcher: %zu/%zu frames tracked, %zu keyframes, %d resets\n",
                r.frontend.c_str(), s.stats.value("matcher", std::string("?")).c_str(), s.tracked_frames, s.frames,
                s.keyframes, s.resets);
  out << line;
  if (s.error) {
    std::snprintf(line, sizeof line, "ATE RMSE   %.4f m = %.2f %% of the %.1f m path (%s alignment, %zu poses)\n",
                  s.error->rmse_m, s.error->percent_of_path, s.error->path_length_m, s.error->align.c_str(),
                  s.error->matched_poses);
  } else {
    std::snprintf(line, sizeof line, "ATE RMSE   not available (too few tracked frames)\n");
  }
  out << line;
  std::snprintf(line, sizeof line, "speed      %.1f frames/s (%.1f s for %zu frames, wall clock)\n", s.frames_per_second,
                s.wall_seconds, s.frames);
  out << line;
  const auto timing = s.stats.value("timing_ms", nlohmann::json::object());
  auto rows = [&](const char* title, const auto& modules) {
    out << title << "\n";
    for (const Module& m : modules) {
      if (!timing.contains(m.key)) continue;
      const auto& t = timing[m.key];
      std::snprintf(line, sizeof line, "  %-22s %8.2f ms mean %8.2f ms p95 %6lld calls %8.0f ms total\n", m.label,
                    t.value("mean", 0.0), t.value("p95", 0.0), t.value("count", 0LL), t.value("total", 0.0));
      out << line;
    }
  };
  rows("tracking thread (per frame):", kTrackingModules);
  rows("keyframe worker (per keyframe):", kKeyframeModules);
  for (const auto& n : r.notices) out << "notice: " << n << "\n";
  if (!r.run_dir.empty()) out << "outputs    " << r.sequence_dir.string() << ", " << r.run_dir.string() << "\n";
  return out.str();
}

}  // namespace pllvo::vo
