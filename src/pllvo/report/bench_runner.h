#pragma once
// `pllvo bench`: every method on every sequence, `repeat` times, aggregated to the median and
// the spread (max - min) of each number; speeds also relative to the speed-baseline method
// measured in the same bench.
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <yaml-cpp/yaml.h>

#include "pllvo/report/bench_methods.h"
#include "pllvo/report/run_metrics.h"

namespace pllvo::report {

struct BenchSequence {
  std::string name;  ///< shown in the table (the folder name)
  std::filesystem::path path;
};

struct BenchOptions {
  std::vector<BenchSequence> sequences;
  std::vector<BenchMethod> methods;
  YAML::Node base_config;                 ///< VO YAML every method starts from (may be null)
  std::vector<ConfigOverride> common;     ///< applied before each method's overrides
  std::vector<ConfigOverride> overrides;  ///< command line --set: applied after the method's
  std::string source = "bench";           ///< names the method table in errors
  std::string speed_baseline = "orb";
  int repeat = 1;
  bool mono = false;        ///< left camera only, also on stereo sequences
  bool rgbd = false;        ///< left camera and its depth images, also on stereo sequences that have them
  size_t first_frame = 0;
  size_t max_frames = 0;    ///< 0: whole sequences
  /// Live-rate playback (vo::LivePlayback): frames arrive at their timestamps / speed, late
  /// ones are dropped; the table adds frames dropped and latency.
  bool realtime = false;
  double speed = 1.0;
  double rpe_delta_s = 1.0; ///< RPE pairs this far apart in time
  std::filesystem::path runs_dir;  ///< when set, each run's outputs go to runs_dir/<seq>/<method>/<k>
  std::function<void(const std::string&)> progress;
};

/// Median, spread (max - min) and count of the finite values among the repeats.
struct Aggregate {
  double median = NAN, spread = NAN;
  size_t n = 0;
};
Aggregate aggregate(std::vector<double> values);

struct BenchCell {
  std::string method, sequence;
  std::vector<RunMetrics> runs;
  std::map<std::string, Aggregate> stats;  ///< by RunMetrics::values() name, plus speed_ratio
  size_t failed = 0;
  std::string error;  ///< the first failure's message
  std::string matcher;  ///< keyframe matcher of the successful runs
};

struct BenchResult {
  std::vector<std::string> methods, sequences;
  std::vector<BenchCell> cells;  ///< sequence-major, methods in the given order
  std::string speed_baseline;
  int repeat = 1;
  bool mono = false;
  bool realtime = false;
  const BenchCell* find(const std::string& method, const std::string& sequence) const;
};

/// Builds every method's config first (a bad override fails before anything runs), then runs.
/// A run that throws is recorded as failed (its message kept) and the bench goes on.
BenchResult run_bench(const BenchOptions& options);

}  // namespace pllvo::report
