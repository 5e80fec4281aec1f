#include "pllvo/report/bench_runner.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include <spdlog/spdlog.h>
#include <sys/resource.h>

#include "pllvo/common/error.h"
#include "pllvo/io/sequence.h"
#include "pllvo/vo/run_sequence.h"

namespace pllvo::report {
namespace {

/// User + system CPU time of this process, all threads, in milliseconds.
double process_cpu_ms() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  auto ms = [](const timeval& t) { return t.tv_sec * 1000.0 + t.tv_usec / 1000.0; };
  return ms(u.ru_utime) + ms(u.ru_stime);
}

std::string format_duration(double s) {
  char buf[32];
  if (s >= 3600)
    std::snprintf(buf, sizeof buf, "%dh%02dm", static_cast<int>(s / 3600), static_cast<int>(std::fmod(s, 3600) / 60));
  else
    std::snprintf(buf, sizeof buf, "%dm%02ds", static_cast<int>(s / 60), static_cast<int>(std::fmod(s, 60)));
  return buf;
}

RunMetrics run_once(const io::Sequence& sequence, const vo::VoConfig& config, const BenchOptions& o,
                    const std::filesystem::path& out_dir, const std::string& prefix) {
  vo::RunOptions run;
  run.out_dir = out_dir;
  run.first_frame = o.first_frame;
  run.max_frames = o.max_frames;
  run.realtime = o.realtime;
  run.speed = o.speed;
  if (o.progress) run.progress = [&](const std::string& line) { o.progress(prefix + line); };
  RunMetrics m;
  try {
    run.choose_sensors(sequence, o.mono, o.rgbd);  // in the try: a sequence without depth is its row's error
    if (!out_dir.empty()) std::filesystem::create_directories(out_dir);
    const double cpu_start = process_cpu_ms();
    const vo::RunSummary s = vo::run_sequence(sequence, config, run);
    const double cpu = process_cpu_ms() - cpu_start;
    add_stats(s.stats, m);
    m.cpu_ms_per_frame = m.frames > 0 ? cpu / m.frames : NAN;
    const double rate = sequence.calibration().rate_hz > 0 ? sequence.calibration().rate_hz : 20.0;
    if (sequence.ground_truth())
      add_trajectory_errors(s.trajectory, *sequence.ground_truth(), s.metric(),
                            static_cast<size_t>(std::lround(o.rpe_delta_s * rate)), m);
  } catch (const std::exception& e) {
    m.error = e.what();
    spdlog::warn("{}failed: {}", prefix, m.error);
  }
  return m;
}

void aggregate_cell(BenchCell& cell) {
  std::map<std::string, std::vector<double>> values;
  for (const auto& r : cell.runs) {
    if (!r.ok()) {
      ++cell.failed;
      if (cell.error.empty()) cell.error = r.error;
      continue;
    }
    for (const auto& [k, v] : r.values()) values[k].push_back(v);
    if (cell.matcher.empty()) cell.matcher = r.matcher;
  }
  for (auto& [k, v] : values) cell.stats[k] = aggregate(v);
}

}  // namespace

Aggregate aggregate(std::vector<double> values) {
  values.erase(std::remove_if(values.begin(), values.end(), [](double v) { return !std::isfinite(v); }),
               values.end());
  Aggregate a;
  a.n = values.size();
  if (values.empty()) return a;
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  a.median = n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
  a.spread = values.back() - values.front();
  return a;
}

const BenchCell* BenchResult::find(const std::string& method, const std::string& sequence) const {
  for (const auto& c : cells)
    if (c.method == method && c.sequence == sequence) return &c;
  return nullptr;
}

BenchResult run_bench(const BenchOptions& o) {
  if (o.sequences.empty()) throw InputError("bench: no sequences (give dataset folders or --synth-suite DIR)");
  if (o.methods.empty()) throw InputError("bench: no methods");
  if (o.repeat < 1) throw InputError("bench: --repeat must be at least 1");

  // Everything that can be wrong with the input is found before the first run.
  std::vector<vo::VoConfig> configs;
  for (const auto& m : o.methods) {
    std::vector<ConfigOverride> all = o.common;
    all.insert(all.end(), m.overrides.begin(), m.overrides.end());
    all.insert(all.end(), o.overrides.begin(), o.overrides.end());
    configs.push_back(make_vo_config(o.base_config, all, o.source + " (method " + m.name + ")"));
  }
  io::SequenceOptions seq_options;
  seq_options.mono = o.mono;
  std::vector<std::unique_ptr<io::Sequence>> sequences;
  for (const auto& s : o.sequences) sequences.push_back(io::open_sequence(s.path, seq_options));

  BenchResult result;
  result.speed_baseline = o.speed_baseline;
  result.repeat = o.repeat;
  result.mono = o.mono;
  result.realtime = o.realtime;
  for (const auto& m : o.methods) result.methods.push_back(m.name);
  for (const auto& s : o.sequences) result.sequences.push_back(s.name);

  const size_t total = o.sequences.size() * o.methods.size() * static_cast<size_t>(o.repeat);
  size_t done = 0;
  const auto start = std::chrono::steady_clock::now();
  for (size_t si = 0; si < sequences.size(); ++si) {
    for (size_t mi = 0; mi < o.methods.size(); ++mi) {
      BenchCell cell;
      cell.method = o.methods[mi].name;
      cell.sequence = o.sequences[si].name;
      for (int k = 0; k < o.repeat; ++k) {
        char prefix[256];
        const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        const std::string eta = done > 0 ? ", eta " + format_duration(elapsed / done * (total - done)) : "";
        std::snprintf(prefix, sizeof prefix, "[%zu/%zu %s%s] %s on %s, run %d/%d: ", done + 1, total,
                      format_duration(elapsed).c_str(), eta.c_str(), cell.method.c_str(), cell.sequence.c_str(),
                      k + 1, o.repeat);
        if (o.progress) o.progress(std::string(prefix) + "start");
        const auto out = o.runs_dir.empty()
                             ? std::filesystem::path()
                             : o.runs_dir / cell.sequence / cell.method / std::to_string(k + 1);
        cell.runs.push_back(run_once(*sequences[si], configs[mi], o, out, prefix));
        ++done;
      }
      aggregate_cell(cell);
      result.cells.push_back(std::move(cell));
    }
    // Speed relative to the baseline measured on the same sequence in this bench: CPU time
    // (robust to other load on the machine) and wall time.
    const BenchCell* base = result.find(o.speed_baseline, o.sequences[si].name);
    for (auto& c : result.cells) {
      if (c.sequence != o.sequences[si].name || !base) continue;
      for (const auto& [key, ratio_key] : {std::pair<std::string, std::string>{"cpu_ms_per_frame", "speed_ratio"},
                                           {"wall_ms_per_frame", "wall_ratio"}}) {
        const auto b = base->stats.find(key);
        if (b == base->stats.end() || !(b->second.median > 0)) continue;
        std::vector<double> ratios;
        for (const auto& r : c.runs)
          if (r.ok()) ratios.push_back(r.values().at(key) / b->second.median);
        c.stats[ratio_key] = aggregate(ratios);
      }
    }
  }
  return result;
}

}  // namespace pllvo::report
