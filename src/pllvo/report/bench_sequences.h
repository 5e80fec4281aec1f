#pragma once
// What `pllvo bench` runs on: dataset folders as given, or a synthetic suite folder whose
// missing members are rendered first (`pllvo synth --suite` layout: DIR/<preset>).
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "pllvo/report/bench_runner.h"

namespace pllvo::report {

/// One entry per folder, named by the folder; InputError when a folder does not exist.
std::vector<BenchSequence> dataset_sequences(const std::vector<std::string>& folders);

struct SynthSuiteOptions {
  std::vector<std::string> presets;  ///< empty: the standard suite (synth::suite_presets())
  double duration_s = 0;             ///< 0: the presets' own (30 s)
  bool stereo = true;                ///< render cam1 too (stereo runs need it; --mono ignores it)
  bool depth = false;                ///< render cam0's depth too (RGB-D runs need it)
  /// Rendering progress: sequence name, frames done, total.
  std::function<void(const std::string&, size_t, size_t)> progress;
};

/// DIR/<preset> for each preset; those missing are rendered (staged and renamed by the synth
/// writer, so an interrupted bench never leaves half a sequence). InputError for an unknown preset.
std::vector<BenchSequence> synth_suite_sequences(const std::filesystem::path& dir, const SynthSuiteOptions& options);

}  // namespace pllvo::report
