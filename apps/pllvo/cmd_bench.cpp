// pllvo bench: baselines and ablations (config/bench.yaml) over datasets or the synthetic
// suite; one table on stdout, the same as JSON and CSV.
#include <cstdio>

#include <unistd.h>

#include "commands.h"
#include "pllvo/common/error.h"
#include "pllvo/common/yaml_config.h"
#include "pllvo/report/bench_methods.h"
#include "pllvo/report/bench_runner.h"
#include "pllvo/report/bench_sequences.h"
#include "pllvo/report/bench_table.h"

namespace pllvo::cli {

namespace {

struct BenchArgs {
  std::vector<std::string> datasets;
  std::string synth_suite;
  std::vector<std::string> synth_presets;
  double synth_duration = 0;
  std::string methods_file = "config/bench.yaml";
  std::vector<std::string> methods;
  std::string config;
  std::vector<std::string> set;
  int repeat = 1;
  bool mono = false;
  bool rgbd = false;
  bool single_thread = false;
  size_t first = 0;
  size_t max_frames = 0;
  std::string out = "bench_out";
  bool keep_runs = false;
  bool realtime = false;
  double speed = 1.0;
};

void run_bench(const BenchArgs& a) {
  if (a.datasets.empty() == a.synth_suite.empty())
    throw InputError("bench: give dataset folders or --synth-suite DIR (one of the two)");
  const auto table = report::load_bench_methods(a.methods_file);

  report::BenchOptions o;
  o.methods = table.select(a.methods, a.methods_file);
  o.common = table.common;
  o.source = a.methods_file;
  o.speed_baseline = table.speed_baseline;
  if (!a.config.empty()) o.base_config = ConfigNode::load_file(a.config).raw();
  for (const auto& s : a.set) o.overrides.push_back(report::parse_override(s));
  if (a.single_thread) o.overrides.push_back(report::parse_override("run.threaded=false"));
  o.repeat = a.repeat;
  o.mono = a.mono;
  o.rgbd = a.rgbd;
  o.first_frame = a.first;
  o.max_frames = a.max_frames;
  o.realtime = a.realtime;
  o.speed = a.speed;
  if (a.keep_runs) o.runs_dir = std::filesystem::path(a.out) / "runs";
  const bool tty = ::isatty(2) != 0;
  o.progress = [tty](const std::string& line) {
    std::fprintf(stderr, tty ? "\r\033[K%s" : "%s\n", line.c_str());
    std::fflush(stderr);
  };

  if (!a.synth_suite.empty()) {
    report::SynthSuiteOptions so;
    so.presets = a.synth_presets;
    so.duration_s = a.synth_duration;
    so.depth = a.rgbd;
    so.progress = [](const std::string& name, size_t done, size_t total) {
      if (done == total || done % 100 == 0) std::fprintf(stderr, "rendering %s: frame %zu/%zu\n", name.c_str(), done, total);
    };
    o.sequences = report::synth_suite_sequences(a.synth_suite, so);
  } else {
    o.sequences = report::dataset_sequences(a.datasets);
  }

  const auto result = report::run_bench(o);
  if (tty) std::fprintf(stderr, "\n");
  const std::string text = report::format_bench_table(result);
  std::printf("%s", text.c_str());
  const std::filesystem::path out(a.out);
  report::write_text_file(out / "bench.txt", text);
  report::write_text_file(out / "bench.csv", report::format_bench_csv(result));
  report::write_text_file(out / "bench.json", report::bench_json(result, o.methods).dump(2) + "\n");
  std::printf("\nmedian over %d run%s (spread = max - min in brackets); times in ms; 'x %s' = CPU time per frame "
              "(all threads) relative to %s on the same sequence\nwritten: %s/{bench.txt, bench.csv, bench.json}\n",
              a.repeat, a.repeat > 1 ? "s" : "", table.speed_baseline.c_str(), table.speed_baseline.c_str(),
              a.out.c_str());
}

}  // namespace

void add_bench_command(CLI::App& app) {
  auto a = std::make_shared<BenchArgs>();
  auto* cmd = app.add_subcommand("bench", "compare baselines and ablations (config/bench.yaml) on datasets");
  cmd->add_option("datasets", a->datasets, "dataset folders (EuRoC, TUM, KITTI, image folder)");
  cmd->add_option("--synth-suite", a->synth_suite,
                  "synthetic suite folder (DIR/<preset>, as `pllvo synth --suite`); missing sequences are rendered");
  cmd->add_option("--synth-presets", a->synth_presets, "suite members to use (default: the whole suite)")
      ->delimiter(',');
  cmd->add_option("--synth-duration", a->synth_duration, "seconds per rendered sequence (default: the presets' 30)");
  cmd->add_option("--methods-file", a->methods_file, "method table (default: config/bench.yaml)");
  cmd->add_option("--methods", a->methods, "methods to run, in order (default: the table's default_methods)")
      ->delimiter(',');
  cmd->add_option("--config", a->config, "VO config YAML every method starts from");
  cmd->add_option("--set", a->set, "extra override key=value for every method (repeatable)");
  cmd->add_option("--repeat", a->repeat, "runs per method and sequence (median and spread reported)")
      ->check(CLI::PositiveNumber);
  cmd->add_flag("--mono", a->mono, "left camera only, also on stereo sequences (Sim3 alignment)");
  cmd->add_flag("--rgbd", a->rgbd,
                "left camera and its depth images (SE3 alignment); a synthetic suite is rendered with depth")
      ->excludes("--mono");
  cmd->add_flag("--single-thread", a->single_thread, "deterministic single-thread VO (run.threaded=false)");
  cmd->add_option("--first", a->first, "first frame index of every sequence");
  cmd->add_option("--max-frames", a->max_frames, "at most this many frames per sequence (0: all)");
  cmd->add_flag("--realtime", a->realtime,
                "live-rate playback: frames arrive at their timestamps, late ones are dropped (table: dropped %, "
                "latency)");
  cmd->add_option("--speed", a->speed, "playback speed factor for --realtime (default 1)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--out", a->out, "folder for bench.txt, bench.csv, bench.json (default: bench_out)");
  cmd->add_flag("--keep-runs", a->keep_runs, "keep every run's outputs in OUT/runs/<sequence>/<method>/<k>");
  cmd->callback([a] { run_bench(*a); });
}

}  // namespace pllvo::cli
