// pllvo demo: renders a short synthetic stereo sequence, runs the odometry on it and prints
// ATE, frames per second and the per-module split (logic: src/pllvo/vo/demo.h).
#include <cstdio>

#include "commands.h"
#include "pllvo/vo/demo.h"
#include "pllvo/vo/vo_config.h"

namespace pllvo::cli {

namespace {

struct DemoArgs {
  vo::DemoOptions options;
  std::string config;
  bool mono = false;
  bool single_thread = false;
};

void run_demo(DemoArgs a) {
  vo::VoConfig config;
  if (!a.config.empty()) config = vo::VoConfig::load(a.config);
  if (a.single_thread) config.run.threaded = false;
  a.options.stereo = !a.mono;
  a.options.log = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };
  const vo::DemoResult result = vo::run_demo(a.options, config);
  std::printf("%s", vo::format_demo_report(result).c_str());
}

}  // namespace

void add_demo_command(CLI::App& app) {
  auto args = std::make_shared<DemoArgs>();
  auto* cmd = app.add_subcommand("demo", "render a synthetic sequence, run the odometry on it, print ATE and speed");
  cmd->add_option("--preset", args->options.preset, "synthetic preset (pllvo synth --list)");
  cmd->add_option("--duration", args->options.duration_s, "seconds of motion (20 frames/s)")
      ->check(CLI::Range(1.0, 600.0));
  cmd->add_option("--seed", args->options.seed, "scene, flight and noise seed");
  cmd->add_option("--out", args->options.out_dir, "keep the sequence and the run's outputs here (default: temporary)");
  cmd->add_option("--frontend", args->options.frontend, "point front end; auto: SuperPoint if its weights are found, else ORB")
      ->check(CLI::IsMember({"auto", "superpoint", "orb", "shitomasi"}));
  cmd->add_option("--config", args->config, "VO config YAML (config/vo.yaml documents the keys)");
  cmd->add_flag("--mono", args->mono, "monocular (left camera only; Sim3 alignment)");
  cmd->add_flag("--single-thread", args->single_thread, "process keyframes inline (deterministic; slower)");
  cmd->callback([args] { run_demo(*args); });
}

}  // namespace pllvo::cli
