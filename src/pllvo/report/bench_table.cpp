#include "pllvo/report/bench_table.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <algorithm>

#include "pllvo/common/error.h"

namespace pllvo::report {
namespace {

std::string fmt(double v, const char* format) {
  if (!std::isfinite(v)) return "-";
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

double median_of(const BenchCell& c, const std::string& key) {
  const auto it = c.stats.find(key);
  return it == c.stats.end() ? NAN : it->second.median;
}

double spread_of(const BenchCell& c, const std::string& key) {
  const auto it = c.stats.find(key);
  return it == c.stats.end() ? NAN : it->second.spread;
}

/// "0.0123 (0.0004)": the median and, with repeats, the spread.
std::string with_spread(const BenchCell& c, const std::string& key, const char* format, int repeat) {
  std::string s = fmt(median_of(c, key), format);
  if (repeat > 1 && s != "-") s += " (" + fmt(spread_of(c, key), format) + ")";
  return s;
}

struct Column {
  std::string header;
  bool left = false;
};

std::string render(const std::vector<Column>& cols, const std::vector<std::vector<std::string>>& rows) {
  std::vector<size_t> width(cols.size());
  for (size_t i = 0; i < cols.size(); ++i) width[i] = cols[i].header.size();
  for (const auto& r : rows)
    for (size_t i = 0; i < r.size(); ++i) width[i] = std::max(width[i], r[i].size());
  auto line = [&](const std::vector<std::string>& cells) {
    std::string s;
    for (size_t i = 0; i < cells.size(); ++i) {
      const size_t pad = width[i] - cells[i].size();
      if (i) s += "  ";
      s += cols[i].left ? cells[i] + std::string(pad, ' ') : std::string(pad, ' ') + cells[i];
    }
    while (!s.empty() && s.back() == ' ') s.pop_back();
    return s + "\n";
  };
  std::vector<std::string> header;
  for (const auto& c : cols) header.push_back(c.header);
  std::string out = line(header);
  size_t total = 0;
  for (size_t w : width) total += w + 2;
  out += std::string(total - 2, '-') + "\n";
  for (const auto& r : rows) out += r.empty() ? "\n" : line(r);
  return out;
}

}  // namespace

std::map<std::string, double> method_means(const BenchResult& result, const std::string& method) {
  std::map<std::string, std::pair<double, int>> sums;
  for (const auto& c : result.cells) {
    if (c.method != method) continue;
    for (const auto& [k, a] : c.stats)
      if (std::isfinite(a.median)) sums[k].first += a.median, sums[k].second += 1;
  }
  std::map<std::string, double> means;
  for (const auto& [k, s] : sums) means[k] = s.first / s.second;
  return means;
}

std::string format_bench_table(const BenchResult& r) {
  std::vector<Column> cols = {
      {"sequence", true}, {"method", true}, {"ATE m"},     {"ATE %"},    {"RPE m"},  {"RPE deg"},
      {"tracked %"},      {"KF"},           {"ms/frame mean"}, {"med"},  {"p95"},    {"wall ms/f"},
      {"cpu ms/f"},       {"x " + r.speed_baseline}, {"pt-ext"}, {"line-ext"}, {"track"}, {"match"}, {"BA"}, {"note", true}};
  // Live-rate runs: frames dropped, latency (arrival to pose) and frames a keyframe's result
  // comes back after, after the keyframe count.
  const std::vector<std::pair<std::string, std::string>> live = {{"dropped %", "dropped_share"},
                                                                 {"latency ms", "latency_mean_ms"},
                                                                 {"lat p95", "latency_p95_ms"},
                                                                 {"kf back", "keyframe_return_frames"}};
  if (r.realtime)
    for (size_t k = 0; k < live.size(); ++k) cols.insert(cols.begin() + 8 + k, Column{live[k].first});
  auto add_live = [&](std::vector<std::string>& row, const std::function<double(const std::string&)>& get) {
    if (!r.realtime) return;
    for (const auto& [title, key] : live) row.push_back(fmt((key == "dropped_share" ? 100 : 1) * get(key), "%.1f"));
  };
  std::vector<std::vector<std::string>> rows;
  for (const auto& seq : r.sequences) {
    for (const auto& method : r.methods) {
      const BenchCell* c = r.find(method, seq);
      if (!c) continue;
      std::vector<std::string> row = {seq, method};
      if (c->failed == c->runs.size()) {
        row.resize(cols.size(), "-");
        row.back() = "FAILED: " + c->error.substr(0, 80);
        rows.push_back(row);
        continue;
      }
      row.push_back(with_spread(*c, "ate_rmse_m", "%.4f", r.repeat));
      row.push_back(fmt(median_of(*c, "ate_percent"), "%.2f"));
      row.push_back(fmt(median_of(*c, "rpe_trans_m"), "%.4f"));
      row.push_back(fmt(median_of(*c, "rpe_rot_deg"), "%.2f"));
      row.push_back(fmt(100 * median_of(*c, "tracked_share"), "%.1f"));
      row.push_back(fmt(median_of(*c, "keyframes"), "%.0f"));
      add_live(row, [&](const std::string& k) { return median_of(*c, k); });
      row.push_back(with_spread(*c, "frame_ms_mean", "%.1f", r.repeat));
      row.push_back(fmt(median_of(*c, "frame_ms_median"), "%.1f"));
      row.push_back(fmt(median_of(*c, "frame_ms_p95"), "%.1f"));
      row.push_back(with_spread(*c, "wall_ms_per_frame", "%.1f", r.repeat));
      row.push_back(with_spread(*c, "cpu_ms_per_frame", "%.1f", r.repeat));
      row.push_back(fmt(median_of(*c, "speed_ratio"), "%.2f"));
      for (const auto& t : module_timers()) row.push_back(fmt(median_of(*c, "ms_" + t.column), "%.1f"));
      std::string note = c->matcher.empty() ? "" : "matcher " + c->matcher;
      const double layers = median_of(*c, "matcher_layers_mean"), pruned = median_of(*c, "matcher_pruned_share");
      if (std::isfinite(layers) && std::isfinite(pruned))
        note += fmt(layers, " (%.2f layers, ") + fmt(100 * pruned, "%.0f%% pruned)");
      if (c->failed)
        note += (note.empty() ? "" : "; ") + std::to_string(c->failed) + " of " + std::to_string(c->runs.size()) +
                " runs failed";
      row.push_back(note);
      rows.push_back(row);
    }
    rows.push_back({});
  }
  if (r.sequences.size() > 1) {
    for (const auto& method : r.methods) {
      const auto m = method_means(r, method);
      auto get = [&](const std::string& k) { return m.count(k) ? m.at(k) : NAN; };
      std::vector<std::string> row = {"mean", method, fmt(get("ate_rmse_m"), "%.4f"), fmt(get("ate_percent"), "%.2f"),
                                      fmt(get("rpe_trans_m"), "%.4f"), fmt(get("rpe_rot_deg"), "%.2f"),
                                      fmt(100 * get("tracked_share"), "%.1f"), fmt(get("keyframes"), "%.0f")};
      add_live(row, get);
      for (const char* k : {"frame_ms_mean", "frame_ms_median", "frame_ms_p95", "wall_ms_per_frame", "cpu_ms_per_frame"})
        row.push_back(fmt(get(k), "%.1f"));
      row.push_back(fmt(get("speed_ratio"), "%.2f"));
      for (const auto& t : module_timers()) row.push_back(fmt(get("ms_" + t.column), "%.1f"));
      row.push_back("");
      rows.push_back(row);
    }
  }
  while (!rows.empty() && rows.back().empty()) rows.pop_back();
  return render(cols, rows);
}

std::string format_bench_csv(const BenchResult& r) {
  std::vector<std::string> keys;
  for (const auto& c : r.cells)
    for (const auto& [k, a] : c.stats)
      if (std::find(keys.begin(), keys.end(), k) == keys.end()) keys.push_back(k);
  std::string out = "sequence,method,runs,failed";
  for (const auto& k : keys) out += "," + k + "," + k + "_spread";
  out += "\n";
  for (const auto& c : r.cells) {
    out += c.sequence + "," + c.method + "," + std::to_string(c.runs.size()) + "," + std::to_string(c.failed);
    for (const auto& k : keys) {
      const auto it = c.stats.find(k);
      // Missing values are empty fields.
      const bool has = it != c.stats.end();
      out += ',';
      if (has && std::isfinite(it->second.median)) out += fmt(it->second.median, "%.6g");
      out += ',';
      if (has && std::isfinite(it->second.spread)) out += fmt(it->second.spread, "%.6g");
    }
    out += "\n";
  }
  return out;
}

nlohmann::json bench_json(const BenchResult& r, const std::vector<BenchMethod>& methods) {
  auto num = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); };
  nlohmann::json j;
  j["repeat"] = r.repeat;
  j["mode"] = r.mono ? "mono" : "stereo (where the sequence has two cameras)";
  j["speed_baseline"] = r.speed_baseline;
  j["sequences"] = r.sequences;
  j["methods"] = nlohmann::json::array();
  for (const auto& m : methods) {
    nlohmann::json set = nlohmann::json::object();
    for (const auto& o : m.overrides) set[o.key] = YAML::Dump(o.value);
    j["methods"].push_back({{"name", m.name}, {"description", m.description}, {"set", set}});
  }
  j["cells"] = nlohmann::json::array();
  for (const auto& c : r.cells) {
    nlohmann::json cell = {{"sequence", c.sequence}, {"method", c.method}, {"matcher", c.matcher}, {"failed", c.failed}};
    if (!c.error.empty()) cell["error"] = c.error;
    for (const auto& [k, a] : c.stats) cell["median"][k] = num(a.median), cell["spread"][k] = num(a.spread);
    cell["runs"] = nlohmann::json::array();
    for (const auto& run : c.runs) {
      nlohmann::json rj;
      if (!run.ok()) rj["error"] = run.error;
      for (const auto& [k, v] : run.values()) rj[k] = num(v);
      cell["runs"].push_back(rj);
    }
    j["cells"].push_back(cell);
  }
  j["mean_over_sequences"] = nlohmann::json::object();
  for (const auto& m : r.methods) {
    nlohmann::json mj = nlohmann::json::object();
    for (const auto& [k, v] : method_means(r, m)) mj[k] = num(v);
    j["mean_over_sequences"][m] = mj;
  }
  return j;
}

void write_text_file(const std::filesystem::path& path, const std::string& text) {
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
  const auto tmp = path.string() + ".tmp";
  {
    std::ofstream f(tmp, std::ios::binary);
    if (!f) throw InputError(path, "cannot write");
    f << text;
    if (!f) throw InputError(path, "cannot write");
  }
  std::filesystem::rename(tmp, path);
}

}  // namespace pllvo::report
