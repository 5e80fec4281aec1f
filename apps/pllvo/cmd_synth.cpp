// pllvo synth: synthetic EuRoC-layout sequences with exact ground truth and hard lighting.
#include <chrono>
#include <cstdio>
#include <memory>

#include <unistd.h>

#include "commands.h"
#include "pllvo/common/error.h"
#include "pllvo/synth/sequence_writer.h"
#include "pllvo/synth/spec.h"

namespace pllvo::cli {

namespace {

struct SynthOptions {
  std::string preset;
  bool suite = false;
  bool list = false;
  std::string out;
  std::string config;
  uint64_t seed = 0;
  double duration = 0;
  bool stereo = false, lines = false, depth = false, overwrite = false;
};

std::string preset_help() {
  std::string s = "Presets (* = in the --suite):\n";
  for (const auto& p : synth::presets())
    s += "  " + p.name + std::string(p.name.size() < 26 ? 26 - p.name.size() : 1, ' ') + (p.in_suite ? "* " : "  ") +
         p.description + "\n";
  return s;
}

/// One progress line per sequence, rewritten in place on a terminal, else every 10%.
class Progress {
 public:
  void operator()(const std::string& name, size_t done, size_t total) {
    const auto now = std::chrono::steady_clock::now();
    if (done == 1 || name != name_) start_ = now, name_ = name, last_decile_ = -1;
    const double secs = std::chrono::duration<double>(now - start_).count();
    const int decile = static_cast<int>(10 * done / total);
    if (!tty_ && decile == last_decile_ && done != total) return;
    last_decile_ = decile;
    std::fprintf(stderr, "%s%s: frame %zu/%zu (%.1f frames/s)%s", tty_ ? "\r" : "", name.c_str(), done, total,
                 secs > 0 ? done / secs : 0.0, (tty_ && done != total) ? "" : "\n");
    std::fflush(stderr);
  }

 private:
  bool tty_ = ::isatty(2) != 0;
  std::string name_;
  std::chrono::steady_clock::time_point start_;
  int last_decile_ = -1;
};

void run_synth(const SynthOptions& o) {
  if (o.list) {
    std::printf("%s", preset_help().c_str());
    return;
  }
  if (!o.suite && o.preset.empty() && o.config.empty())
    throw InputError("synth: give --preset NAME, --config FILE or --suite (see pllvo synth --help)");
  if (o.suite && !o.preset.empty()) throw InputError("synth: --suite and --preset exclude each other");
  if (o.out.empty()) throw InputError("synth: --out DIR is required");

  // Precedence: preset < --config file < command-line flags.
  auto apply_flags = [&](synth::SequenceSpec& spec) {
    if (o.seed) spec.seed = o.seed;
    if (o.duration > 0) spec.duration_s = o.duration;
    if (o.stereo) spec.camera.stereo = true;
    if (o.lines) spec.output.lines = true;
    if (o.depth) spec.output.depth = true;
    synth::validate(spec, o.config);
  };
  auto apply_config = [&](synth::SequenceSpec& spec) {
    if (o.config.empty()) return;
    const std::string name = spec.name;
    synth::apply_yaml(ConfigNode::load_file(o.config), spec);
    if (o.suite) spec.name = name;  // each suite member keeps its preset's name
  };
  Progress progress;
  synth::WriteOptions wo;
  wo.overwrite = o.overwrite;
  wo.progress = [&](const std::string& name, size_t done, size_t total) { progress(name, done, total); };

  if (o.suite) {
    const auto dirs = synth::write_suite(o.out, [&](synth::SequenceSpec& spec) {
      apply_config(spec);
      apply_flags(spec);
    }, wo);
    for (const auto& d : dirs) std::printf("%s\n", d.string().c_str());
    return;
  }
  synth::SequenceSpec spec;
  if (o.preset.empty()) {
    spec = synth::load_spec(o.config);
  } else {
    spec = synth::preset(o.preset);
    apply_config(spec);
  }
  apply_flags(spec);
  synth::write_sequence(spec, o.out, wo);
  std::printf("%s\n", o.out.c_str());
}

}  // namespace

void add_synth_command(CLI::App& app) {
  auto opts = std::make_shared<SynthOptions>();
  auto* cmd = app.add_subcommand("synth", "render synthetic EuRoC-layout sequences with exact ground truth");
  cmd->add_option("--preset", opts->preset, "preset to render (see the list below)");
  cmd->add_flag("--suite", opts->suite, "render the standard suite into DIR/<preset>");
  cmd->add_flag("--list", opts->list, "print the presets and exit");
  cmd->add_option("--out", opts->out, "output folder (must not exist unless --overwrite)");
  cmd->add_option("--config", opts->config,
                  "YAML spec (keys as in config/synth.yaml); with --preset/--suite it overrides the preset");
  cmd->add_option("--seed", opts->seed, "random seed (scene, flight, noise); default: the preset's (1)");
  cmd->add_option("--duration", opts->duration, "seconds of motion (default: 30)");
  cmd->add_flag("--stereo", opts->stereo, "add cam1, 0.11 m to the right of cam0 (rectified pair)");
  cmd->add_flag("--lines", opts->lines, "write ground-truth 2-D line segments per frame");
  cmd->add_flag("--depth", opts->depth, "write depth per frame (16-bit PNG, millimetres)");
  cmd->add_flag("--overwrite", opts->overwrite, "replace existing output folders");
  cmd->footer(preset_help());
  cmd->callback([opts] { run_synth(*opts); });
}

}  // namespace pllvo::cli
