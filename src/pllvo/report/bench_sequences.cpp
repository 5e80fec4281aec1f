#include "pllvo/report/bench_sequences.h"

#include <spdlog/spdlog.h>

#include "pllvo/common/error.h"
#include "pllvo/synth/sequence_writer.h"
#include "pllvo/synth/spec.h"

namespace pllvo::report {

std::vector<BenchSequence> dataset_sequences(const std::vector<std::string>& folders) {
  std::vector<BenchSequence> out;
  for (const auto& f : folders) {
    const std::filesystem::path p(f);
    if (!std::filesystem::is_directory(p)) throw InputError(p, "no such dataset folder");
    const auto name = p.filename().empty() ? p.parent_path().filename() : p.filename();
    out.push_back({name.string(), p});
  }
  return out;
}

std::vector<BenchSequence> synth_suite_sequences(const std::filesystem::path& dir, const SynthSuiteOptions& o) {
  const auto presets = o.presets.empty() ? synth::suite_presets() : o.presets;
  std::vector<synth::SequenceSpec> specs;
  for (const auto& name : presets) specs.push_back(synth::preset(name));  // InputError for an unknown name first
  std::vector<BenchSequence> out;
  for (auto& spec : specs) {
    const auto folder = dir / spec.name;
    if (!std::filesystem::exists(folder)) {
      if (o.duration_s > 0) spec.duration_s = o.duration_s;
      spec.camera.stereo = o.stereo;
      spec.output.depth = spec.output.depth || o.depth;
      synth::validate(spec);
      spdlog::info("rendering the missing suite sequence {} ({} s{})", folder.string(), spec.duration_s,
                   std::string(o.stereo ? ", stereo" : "") + (o.depth ? ", depth" : ""));
      synth::WriteOptions wo;
      wo.progress = o.progress;
      synth::write_sequence(spec, folder, wo);
    }
    out.push_back({spec.name, folder});
  }
  return out;
}

}  // namespace pllvo::report
