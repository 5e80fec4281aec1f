#pragma once
// The methods `pllvo bench` compares: each is a name, a description and a set of VO config
// overrides (config/bench.yaml documents them). Baselines and ablations are data, not code.
#include <filesystem>
#include <string>
#include <vector>

#include "pllvo/report/config_overrides.h"

namespace pllvo::report {

struct BenchMethod {
  std::string name;
  std::string description;
  std::vector<ConfigOverride> overrides;  ///< applied to the base VO config, in order
};

struct BenchMethodTable {
  std::vector<ConfigOverride> common;  ///< `common:` overrides, applied before each method's
  std::vector<BenchMethod> methods;    ///< in file order
  std::vector<std::string> default_methods;  ///< `default_methods:`; empty: all
  std::string speed_baseline = "orb";  ///< speeds are also reported relative to this method

  /// The named methods in the given order (all defaults when `names` is empty); InputError
  /// naming the file for an unknown name.
  std::vector<BenchMethod> select(const std::vector<std::string>& names, const std::filesystem::path& file) const;
};

/// Reads config/bench.yaml:
///   speed_baseline: orb
///   common: {run.progress_interval_s: 2}
///   methods:
///     - name: orb
///       description: ...
///       set: {frontend.type: orb, mapping.use_lines: false}
/// InputError (file, key) for a missing name, a duplicate, or an unknown key.
BenchMethodTable load_bench_methods(const std::filesystem::path& file);

}  // namespace pllvo::report
