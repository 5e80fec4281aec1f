#include "pllvo/vo/run_stats.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace pllvo::vo {
namespace {

double quantile(const std::vector<double>& sorted, double q) {
  if (sorted.empty()) return 0;
  const double pos = q * static_cast<double>(sorted.size() - 1);
  const size_t lo = static_cast<size_t>(std::floor(pos));
  const size_t hi = std::min(lo + 1, sorted.size() - 1);
  return sorted[lo] + (pos - static_cast<double>(lo)) * (sorted[hi] - sorted[lo]);
}

nlohmann::json timing_json(const TimingSummary& t) {
  return {{"count", t.count}, {"mean", t.mean_ms},   {"median", t.median_ms},
          {"p95", t.p95_ms},  {"max", t.max_ms},     {"total", t.total_ms}};
}

}  // namespace

TimingSummary summarize_timing(std::vector<double> samples_ms) {
  TimingSummary s;
  if (samples_ms.empty()) return s;
  std::sort(samples_ms.begin(), samples_ms.end());
  s.count = samples_ms.size();
  s.total_ms = std::accumulate(samples_ms.begin(), samples_ms.end(), 0.0);
  s.mean_ms = s.total_ms / static_cast<double>(s.count);
  s.median_ms = quantile(samples_ms, 0.5);
  s.p95_ms = quantile(samples_ms, 0.95);
  s.max_ms = samples_ms.back();
  return s;
}

void RunStats::add_time(const std::string& module, double ms) {
  std::lock_guard<std::mutex> lock(mutex_);
  times_[module].push_back(ms);
}

void RunStats::add_count(const std::string& name, long long n) {
  std::lock_guard<std::mutex> lock(mutex_);
  counts_[name] += n;
}

void RunStats::add_sample(const std::string& name, double value) {
  std::lock_guard<std::mutex> lock(mutex_);
  samples_[name].push_back(value);
}

std::map<std::string, TimingSummary> RunStats::timing() const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::map<std::string, TimingSummary> out;
  for (const auto& [name, v] : times_) out[name] = summarize_timing(v);
  return out;
}

std::map<std::string, long long> RunStats::counts() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return counts_;
}

long long RunStats::count(const std::string& name) const {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = counts_.find(name);
  return it == counts_.end() ? 0 : it->second;
}

nlohmann::json RunStats::to_json() const {
  nlohmann::json j;
  j["timing_ms"] = nlohmann::json::object();
  for (const auto& [name, t] : timing()) j["timing_ms"][name] = timing_json(t);
  j["counts"] = counts();
  std::lock_guard<std::mutex> lock(mutex_);
  j["per_frame"] = nlohmann::json::object();
  for (const auto& [name, v] : samples_) {
    std::vector<double> sorted = v;
    std::sort(sorted.begin(), sorted.end());
    const double mean = sorted.empty() ? 0 : std::accumulate(sorted.begin(), sorted.end(), 0.0) / sorted.size();
    j["per_frame"][name] = {{"count", sorted.size()},
                            {"mean", mean},
                            {"median", quantile(sorted, 0.5)},
                            {"min", sorted.empty() ? 0 : sorted.front()},
                            {"max", sorted.empty() ? 0 : sorted.back()}};
  }
  return j;
}

}  // namespace pllvo::vo
