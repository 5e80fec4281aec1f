#include "pllvo/report/report_page.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include <spdlog/spdlog.h>

#include "pllvo/common/error.h"
#include "pllvo/eval/evaluator.h"
#include "pllvo/io/sequence.h"
#include "pllvo/report/bench_table.h"
#include "pllvo/report/svg_plot.h"

namespace pllvo::report {
namespace {

constexpr const char* kEstimateColor = "#d62728";
constexpr const char* kTruthColor = "#222222";

std::string read_file(const std::filesystem::path& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError(path, "cannot read");
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

std::vector<double> component(const std::vector<Eigen::Vector3d>& v, int axis) {
  std::vector<double> out;
  out.reserve(v.size());
  for (const auto& p : v) out.push_back(p[axis]);
  return out;
}

std::string fmt(const char* format, double v) {
  if (!std::isfinite(v)) return "-";
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

/// Chart of one component over time: estimate against ground truth.
std::string component_chart(const PlotSeries& s, const std::vector<Eigen::Vector3d>& est,
                            const std::vector<Eigen::Vector3d>& gt, int axis, const std::string& title,
                            const std::string& unit, const std::string& id) {
  LineChart chart(title, "time [s]", unit);
  chart.set_id(id);
  if (!gt.empty()) chart.add({"ground truth", kTruthColor, s.t, component(gt, axis)});
  chart.add({"estimate", kEstimateColor, s.t, component(est, axis)});
  return chart.render(386, 230);
}

}  // namespace

std::array<int, 3> axes_by_extent(const std::vector<Eigen::Vector3d>& points) {
  Eigen::Vector3d extent = Eigen::Vector3d::Zero();
  if (!points.empty()) {
    Eigen::Vector3d lo = points.front(), hi = points.front();
    for (const auto& p : points) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    extent = hi - lo;
  }
  std::array<int, 3> axes{0, 1, 2};
  std::stable_sort(axes.begin(), axes.end(), [&](int a, int b) { return extent[a] > extent[b]; });
  return axes;
}

namespace {

/// `a` and `b` in increasing axis order, so that x comes before z whichever spread more.
std::string view_chart(const PlotSeries& s, int a, int b, const std::string& title, const std::string& id) {
  if (a > b) std::swap(a, b);
  static const char* names[] = {"x [m]", "y [m]", "z [m]"};
  LineChart chart(title, names[a], names[b]);
  chart.set_id(id);
  chart.set_equal_aspect(true);
  if (!s.gt_xyz.empty()) chart.add({"ground truth", kTruthColor, component(s.gt_xyz, a), component(s.gt_xyz, b)});
  chart.add({"estimate", kEstimateColor, component(s.est_xyz, a), component(s.est_xyz, b)});
  return chart.render(586, 440);
}

/// The plane of largest motion and, beside it, the largest axis against the smallest (the path's height or depth).
std::string trajectory_views(const PlotSeries& s) {
  static const char* letters = "xyz";
  const auto axes = axes_by_extent(s.gt_xyz.empty() ? s.est_xyz : s.gt_xyz);
  const auto plane = [&](int a, int b) {
    if (a > b) std::swap(a, b);
    return std::string(1, letters[a]) + "-" + letters[b];
  };
  return view_chart(s, axes[0], axes[1], "plane of largest motion (" + plane(axes[0], axes[1]) + ")", "top") +
         view_chart(s, axes[0], axes[2], "across it (" + plane(axes[0], axes[2]) + ")", "side");
}

std::string timing_chart(const nlohmann::json& stats) {
  BarChart chart("time per call by module (mean; light: p95)", "milliseconds per call");
  const auto timing = stats.value("timing_ms", nlohmann::json::object());
  std::vector<std::pair<double, std::string>> order;
  for (auto it = timing.begin(); it != timing.end(); ++it)
    if (it.value().contains("mean")) order.push_back({it.value()["mean"].get<double>(), it.key()});
  std::sort(order.rbegin(), order.rend());
  for (const auto& [mean, name] : order) {
    const auto& t = timing[name];
    chart.add(name + " (" + std::to_string(t.value("count", 0)) + "x)", mean, t.value("p95", 0.0));
  }
  return chart.render(1180);
}

std::string summary_table(const ReportInput& in, const PlotSeries& s) {
  const auto& j = in.stats;
  auto str = [&](const char* k) {
    if (!j.contains(k)) return std::string("-");
    return j[k].is_string() ? j[k].get<std::string>() : j[k].dump();
  };
  std::ostringstream o;
  o << "<table class=\"summary\">\n";
  auto row = [&](const std::string& k, const std::string& v) {
    o << "<tr><th>" << xml_escape(k) << "</th><td>" << xml_escape(v) << "</td></tr>\n";
  };
  row("sequence", str("sequence"));
  row("mode / front end / matcher", str("mode") + " / " + str("frontend") + " / " + str("matcher"));
  if (j.contains("pipeline") && j["pipeline"].is_object()) {
    std::string switches;
    for (auto it = j["pipeline"].begin(); it != j["pipeline"].end(); ++it)
      switches += (switches.empty() ? "" : ", ") + it.key() + " " +
                  (it.value().is_string() ? it.value().get<std::string>() : it.value().dump());
    row("pipeline", switches);
  }
  row("frames tracked", str("tracked_frames") + " of " + str("frames"));
  row("keyframes", str("keyframes"));
  row("re-initialisations", str("resets"));
  row("frames per second (wall)", fmt("%.1f", j.value("frames_per_second", NAN)));
  if (std::isfinite(s.ate_rmse_m)) {
    std::string ate = fmt("%.4f m", s.ate_rmse_m) + " (" + s.align + " alignment";
    if (s.align == "sim3") ate += ", scale " + fmt("%.4f", s.scale);
    row("ATE RMSE", ate + ")");
  } else {
    row("ATE RMSE", "no ground truth");
  }
  o << "</table>\n";
  return o.str();
}

constexpr const char* kStyle = R"(
body { font-family: sans-serif; margin: 16px; background: #f4f4f4; color: #222; max-width: 1200px; }
h1 { font-size: 22px; } h2 { font-size: 17px; margin-top: 28px; }
.row { display: flex; flex-wrap: wrap; gap: 8px; }
svg.plot { background: white; border: 1px solid #ccc; }
table.summary { border-collapse: collapse; background: white; }
table.summary th, table.summary td { border: 1px solid #ccc; padding: 3px 10px; text-align: left; }
.frames img { width: 586px; border: 1px solid #ccc; }
.note { color: #a33; }
)";

}  // namespace

Eigen::Vector3d roll_pitch_yaw_deg(const Eigen::Matrix3d& R) {
  const double pitch = std::asin(std::clamp(-R(2, 0), -1.0, 1.0));
  const double roll = std::atan2(R(2, 1), R(2, 2));
  const double yaw = std::atan2(R(1, 0), R(0, 0));
  return Eigen::Vector3d(roll, pitch, yaw) * (180.0 / M_PI);
}

void unwrap_degrees(std::vector<double>& a) {
  double offset = 0;
  for (size_t i = 1; i < a.size(); ++i) {
    const double raw = a[i] + offset;
    const double d = raw - a[i - 1];
    if (d > 180) offset -= 360 * std::round(d / 360);
    if (d < -180) offset += 360 * std::round(-d / 360);
    a[i] += offset;
  }
}

PlotSeries plot_series(const io::Trajectory& estimate, const std::optional<io::Trajectory>& ground_truth,
                       bool metric_scale) {
  PlotSeries s;
  s.align = "none";
  eval::PoseList est_poses, gt_poses;
  std::vector<double> stamps;
  if (ground_truth && ground_truth->has_stamps() && estimate.size() >= 3) {
    eval::EvalOptions options;
    options.align = metric_scale ? eval::AlignMode::se3 : eval::AlignMode::sim3;
    try {
      const eval::Evaluator evaluator(options);
      const auto prepared = evaluator.prepare(*ground_truth, estimate);
      est_poses = prepared.est;
      gt_poses = prepared.ref;
      for (size_t i : prepared.association->est_indices) stamps.push_back(estimate.stamps[i]);
      const auto ape = evaluator.ape(prepared, eval::PoseRelation::trans_part);
      s.error_m = ape.errors;
      s.ate_rmse_m = ape.stats.rmse;
      if (prepared.alignment) s.scale = prepared.alignment->transform.scale;
      s.align = metric_scale ? "se3" : "sim3";
    } catch (const std::exception& e) {
      spdlog::warn("report: estimate not aligned to the ground truth: {}", e.what());
      est_poses.clear(), gt_poses.clear(), stamps.clear();
    }
  }
  if (est_poses.empty()) {
    est_poses.assign(estimate.poses.begin(), estimate.poses.end());
    stamps = estimate.stamps;
  }
  const double t0 = stamps.empty() ? 0 : stamps.front();
  std::vector<double> rpy[2][3];
  for (size_t i = 0; i < est_poses.size(); ++i) {
    s.t.push_back(i < stamps.size() ? stamps[i] - t0 : static_cast<double>(i));
    s.est_xyz.push_back(est_poses[i].translation());
    const auto e = roll_pitch_yaw_deg(est_poses[i].linear());
    for (int k = 0; k < 3; ++k) rpy[0][k].push_back(e[k]);
    if (!gt_poses.empty()) {
      s.gt_xyz.push_back(gt_poses[i].translation());
      const auto g = roll_pitch_yaw_deg(gt_poses[i].linear());
      for (int k = 0; k < 3; ++k) rpy[1][k].push_back(g[k]);
    }
  }
  for (auto& side : rpy)
    for (auto& a : side) unwrap_degrees(a);
  for (size_t i = 0; i < s.t.size(); ++i) {
    s.est_rpy.emplace_back(rpy[0][0][i], rpy[0][1][i], rpy[0][2][i]);
    if (!gt_poses.empty()) s.gt_rpy.emplace_back(rpy[1][0][i], rpy[1][1][i], rpy[1][2][i]);
  }
  return s;
}

std::string base64_encode(const std::string& bytes) {
  static constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const unsigned v = (static_cast<unsigned char>(bytes[i]) << 16) | (static_cast<unsigned char>(bytes[i + 1]) << 8) |
                       static_cast<unsigned char>(bytes[i + 2]);
    out += kAlphabet[(v >> 18) & 63], out += kAlphabet[(v >> 12) & 63], out += kAlphabet[(v >> 6) & 63],
        out += kAlphabet[v & 63];
  }
  if (i < bytes.size()) {
    unsigned v = static_cast<unsigned char>(bytes[i]) << 16;
    if (i + 1 < bytes.size()) v |= static_cast<unsigned char>(bytes[i + 1]) << 8;
    out += kAlphabet[(v >> 18) & 63], out += kAlphabet[(v >> 12) & 63];
    out += i + 1 < bytes.size() ? kAlphabet[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

ReportInput load_run(const std::filesystem::path& run_dir, const std::filesystem::path& ground_truth_file) {
  if (!std::filesystem::is_directory(run_dir)) throw InputError(run_dir, "no such run folder");
  ReportInput in;
  const auto traj = run_dir / "trajectory.tum";
  const auto stats = run_dir / "stats.json";
  if (!std::filesystem::is_regular_file(traj)) throw InputError(traj, "missing (is this a `pllvo run --out` folder?)");
  if (!std::filesystem::is_regular_file(stats)) throw InputError(stats, "missing (is this a `pllvo run --out` folder?)");
  try {
    in.stats = nlohmann::json::parse(read_file(stats));
  } catch (const nlohmann::json::exception& e) {
    throw InputError(stats, std::string("malformed JSON: ") + e.what());
  }
  if (!in.stats.is_object()) throw InputError(stats, "expected a JSON object");
  // An empty trajectory (nothing tracked) is a valid run; read_tum may reject an empty file.
  if (std::filesystem::file_size(traj) > 0) in.estimate = io::read_tum(traj);
  in.metric_scale = in.stats.value("mode", "stereo") == "stereo";
  in.title = "pllvo run: " + std::filesystem::path(in.stats.value("sequence", run_dir.string())).filename().string();
  if (!ground_truth_file.empty()) {
    in.ground_truth = io::read_trajectory(ground_truth_file);
  } else if (in.stats.contains("sequence")) {
    const std::filesystem::path seq = in.stats["sequence"].get<std::string>();
    try {
      io::SequenceOptions options;
      options.format = in.stats.value("format", "auto");
      options.mono = !in.metric_scale;
      const auto sequence = io::open_sequence(seq, options);
      in.ground_truth = sequence->ground_truth();
      if (!in.ground_truth) in.note = "the dataset has no ground truth";
    } catch (const std::exception& e) {
      in.note = "ground truth not shown: the dataset could not be opened (" + std::string(e.what()) +
                "); pass it with --ground-truth";
    }
  }
  const auto frames = run_dir / "frames";
  if (std::filesystem::is_directory(frames)) {
    for (const auto& e : std::filesystem::directory_iterator(frames))
      if (e.path().extension() == ".png") in.frames.push_back(e.path());
    // frame_<index>.png in frame order
    std::sort(in.frames.begin(), in.frames.end(), [](const auto& a, const auto& b) {
      const auto n = [](const std::filesystem::path& p) {
        const auto s = p.stem().string();
        const auto u = s.find_last_of('_');
        try {
          return std::stol(s.substr(u == std::string::npos ? 0 : u + 1));
        } catch (...) {
          return 0L;
        }
      };
      return n(a) < n(b);
    });
  }
  return in;
}

std::string render_report(const ReportInput& in) {
  const PlotSeries s = plot_series(in.estimate, in.ground_truth, in.metric_scale);
  std::ostringstream o;
  o << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>" << xml_escape(in.title) << "</title>\n<style>"
    << kStyle << "</style></head>\n<body>\n<h1>" << xml_escape(in.title) << "</h1>\n";
  if (!in.note.empty()) o << "<p class=\"note\">" << xml_escape(in.note) << "</p>\n";
  o << summary_table(in, s);
  if (s.t.empty()) {
    o << "<p class=\"note\">No frame was tracked: nothing to plot.</p>\n";
  } else {
    const std::string versus = s.gt_xyz.empty() ? "" : " against ground truth (" + s.align + " aligned)";
    o << "<h2>Trajectory" << xml_escape(versus) << "</h2>\n<div class=\"row\" id=\"trajectory\">\n"
      << trajectory_views(s) << "</div>\n";
    if (!s.error_m.empty()) {
      LineChart chart("absolute translation error (APE) over time, RMSE " + fmt("%.4f m", s.ate_rmse_m), "time [s]",
                      "error [m]");
      chart.set_id("error");
      chart.add({"", kEstimateColor, s.t, s.error_m});
      o << "<h2>Error over time</h2>\n<div class=\"row\" id=\"error\">\n" << chart.render(1180, 260) << "</div>\n";
    }
    o << "<h2>Position</h2>\n<div class=\"row\" id=\"position\">\n";
    const char* axes[] = {"x", "y", "z"};
    for (int k = 0; k < 3; ++k)
      o << component_chart(s, s.est_xyz, s.gt_xyz, k, axes[k], std::string(axes[k]) + " [m]", std::string("p") + axes[k]);
    o << "</div>\n<h2>Orientation (roll-pitch-yaw of T_world_cam)</h2>\n<div class=\"row\" id=\"orientation\">\n";
    const char* angles[] = {"roll", "pitch", "yaw"};
    for (int k = 0; k < 3; ++k)
      o << component_chart(s, s.est_rpy, s.gt_rpy, k, angles[k], std::string(angles[k]) + " [deg]", angles[k]);
    o << "</div>\n";
  }
  o << "<h2>Timing</h2>\n<div class=\"row\" id=\"timing\">\n" << timing_chart(in.stats) << "</div>\n";
  if (!in.frames.empty()) {
    o << "<h2>Frames (points: green = map, yellow = candidate; lines: red = map, blue = candidate)</h2>\n"
         "<div class=\"row frames\">\n";
    for (const auto& f : in.frames)
      o << "<img alt=\"" << xml_escape(f.filename().string()) << "\" src=\"data:image/png;base64,"
        << base64_encode(read_file(f)) << "\">\n";
    o << "</div>\n";
  }
  o << "</body></html>\n";
  return o.str();
}

std::filesystem::path write_report(const std::filesystem::path& run_dir, const std::filesystem::path& out,
                                   const std::filesystem::path& ground_truth_file) {
  const auto input = load_run(run_dir, ground_truth_file);
  const auto path = out.empty() ? run_dir / "report.html" : out;
  write_text_file(path, render_report(input));
  return path;
}

}  // namespace pllvo::report
