#pragma once
// `pllvo demo`: the whole product in one command on a fresh clone. Renders a short synthetic
// stereo sequence with exact ground truth (synth module), runs the odometry on it and reports
// the trajectory error, the frame rate and where the time went.
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "pllvo/vo/run_sequence.h"
#include "pllvo/vo/vo_config.h"

namespace pllvo::vo {

struct DemoOptions {
  std::string preset = "easy_normal";  ///< a `pllvo synth --list` preset
  double duration_s = 12;              ///< seconds of motion (20 frames/s)
  uint64_t seed = 1;
  bool stereo = true;
  /// Where the sequence and the run's outputs go (<out>/sequence, <out>/run); empty: a
  /// temporary folder, removed afterwards.
  std::filesystem::path out_dir;
  /// auto: SuperPoint when its weights are found, else ORB (with a notice); or a front end name.
  std::string frontend = "auto";
  /// Progress and notices (a line each); may be empty.
  std::function<void(const std::string&)> log;
};

struct DemoResult {
  std::string preset;
  std::string frontend;              ///< the front end that ran
  std::vector<std::string> notices;  ///< e.g. the ORB fallback
  double render_seconds = 0;
  std::filesystem::path sequence_dir;  ///< empty when it was temporary
  std::filesystem::path run_dir;
  RunSummary summary;
};

/// The front end "auto" resolves to with this config: superpoint when SuperPoint weights are
/// found (frontend.superpoint_weights, then the nn lookup), else orb; `notice` says why.
std::string resolve_frontend(const FrontendConfig& config, std::string* notice = nullptr);

/// Renders the sequence, runs the odometry with `config` (its frontend.type replaced by
/// options.frontend, "auto" resolved by resolve_frontend) and returns what it measured.
DemoResult run_demo(const DemoOptions& options, VoConfig config);

/// The report `pllvo demo` prints: ATE RMSE (m and % of the path), frames per second and
/// the per-module split of the tracking thread and the keyframe worker.
std::string format_demo_report(const DemoResult& result);

}  // namespace pllvo::vo
