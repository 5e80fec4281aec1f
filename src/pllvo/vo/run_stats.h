#pragma once
// Per-module timing and counters of one run, filled from the tracking thread and the
// keyframe worker alike (thread-safe), summarised into stats.json.
#include <chrono>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace pllvo::vo {

struct TimingSummary {
  size_t count = 0;
  double mean_ms = 0, median_ms = 0, p95_ms = 0, max_ms = 0, total_ms = 0;
};

/// Summary of a sample of durations; p95 by linear interpolation between order statistics.
TimingSummary summarize_timing(std::vector<double> samples_ms);

class RunStats {
 public:
  void add_time(const std::string& module, double ms);
  void add_count(const std::string& name, long long n = 1);
  /// Records a sample of a per-frame quantity (tracked points, lines, matches...).
  void add_sample(const std::string& name, double value);

  std::map<std::string, TimingSummary> timing() const;
  std::map<std::string, long long> counts() const;
  long long count(const std::string& name) const;
  nlohmann::json to_json() const;  ///< {"timing_ms": {...}, "counts": {...}, "per_frame": {...}}

 private:
  mutable std::mutex mutex_;
  std::map<std::string, std::vector<double>> times_;
  std::map<std::string, long long> counts_;
  std::map<std::string, std::vector<double>> samples_;
};

/// Adds the elapsed wall time (plus `earlier_ms`, time spent on the same work elsewhere) to
/// `stats` under `module` when it goes out of scope.
class ScopedTimer {
 public:
  ScopedTimer(RunStats& stats, std::string module, double earlier_ms = 0.0)
      : stats_(stats), module_(std::move(module)), earlier_ms_(earlier_ms), start_(std::chrono::steady_clock::now()) {}
  ~ScopedTimer() { stats_.add_time(module_, earlier_ms_ + elapsed_ms()); }
  double elapsed_ms() const {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  RunStats& stats_;
  std::string module_;
  double earlier_ms_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace pllvo::vo
