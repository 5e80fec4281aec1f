#pragma once
// Renders whole sequences to disk in the EuRoC ASL layout, with the synthetic extras:
//   <out>/synth.yaml                         the spec that made it (load_spec() reads it back)
//   <out>/mav0/camN/exposure.csv             #timestamp [ns],exposure_ms,gain,light_level,subframes
//   <out>/mav0/camN/lines/<ns>.csv           (spec.output.lines) visible edge pieces:
//                                            #x1,y1,x2,y2,id,kind,t1,t2,contrast
//   <out>/mav0/lines3d.csv                   (spec.output.lines) #id,kind,x1,y1,z1,x2,y2,z2,quad1,quad2
//   <out>/mav0/camN/depth/<ns>.png           (spec.output.depth) uint16 z in millimetres, 0 = none
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "pllvo/synth/spec.h"

namespace pllvo::synth {

struct WriteOptions {
  bool overwrite = false;
  /// Called after every frame with the sequence name, frames done and the total.
  std::function<void(const std::string& name, size_t done, size_t total)> progress;
};

/// Renders `spec` into `out_dir` (staged, then renamed: nothing half-written on error).
void write_sequence(const SequenceSpec& spec, const std::filesystem::path& out_dir, const WriteOptions& options = {});

/// Renders every suite preset into out_root/<name>, each after `customise` (seed, duration,
/// stereo, outputs...). Returns the folders written.
std::vector<std::filesystem::path> write_suite(const std::filesystem::path& out_root,
                                               const std::function<void(SequenceSpec&)>& customise,
                                               const WriteOptions& options = {});

}  // namespace pllvo::synth
