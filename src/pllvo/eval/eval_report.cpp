#include "pllvo/eval/eval_report.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <system_error>

#include <unistd.h>

#include "pllvo/common/error.h"
#include "pllvo/eval/eval_error.h"
#include "pllvo/geometry/pose.h"

namespace pllvo::eval {

namespace fs = std::filesystem;

namespace {

std::string metric_name(Metric m) { return m == Metric::ape ? "APE" : "RPE"; }

std::string format(const char* fmt, auto... args) {
  char buf[512];
  std::snprintf(buf, sizeof(buf), fmt, args...);
  return buf;
}

std::string delta_text(const PairOptions& rpe) {
  return format(rpe.unit == DeltaUnit::frames ? "%.0f %s, %s" : "%g %s, %s", rpe.delta,
                std::string(delta_unit_name(rpe.unit)).c_str(), rpe.all_pairs ? "all pairs" : "consecutive pairs");
}

nlohmann::json stats_json(const Statistics& s) {
  return {{"rmse", s.rmse}, {"mean", s.mean}, {"median", s.median}, {"std", s.std},
          {"min", s.min},   {"max", s.max},   {"sse", s.sse}};
}

nlohmann::json matrix_json(const Eigen::MatrixXd& m) {
  auto rows = nlohmann::json::array();
  for (Eigen::Index r = 0; r < m.rows(); ++r) {
    auto row = nlohmann::json::array();
    for (Eigen::Index c = 0; c < m.cols(); ++c) row.push_back(m(r, c));
    rows.push_back(row);
  }
  return rows;
}

}  // namespace

std::vector<Metric> parse_metrics(const std::string& name) {
  if (name == "ape") return {Metric::ape};
  if (name == "rpe") return {Metric::rpe};
  if (name == "both") return {Metric::ape, Metric::rpe};
  throw InputError("unknown metric '" + name + "' (use ape, rpe or both)");
}

EvalReport run_evaluation(const EvalRequest& request) {
  const Evaluator evaluator(request.options);
  const auto input = load_trajectories(request.est_file, request.ref_file, request.ref_format);
  EvalReport report;
  report.request = request;
  try {
    report.prepared = evaluator.prepare(input.ref, input.est);
    for (const Metric metric : request.metrics)
      for (const PoseRelation relation : request.relations)
        report.results.push_back(metric == Metric::ape ? evaluator.ape(report.prepared, relation)
                                                       : evaluator.rpe(report.prepared, relation));
  } catch (const InputError& e) {
    if (!e.file().empty()) throw;
    // Evaluation errors concern the pair of files: name both.
    throw InputError(request.est_file, std::string("compared with ") + request.ref_file.string() + ": " + e.what());
  }
  return report;
}

std::string format_report(const EvalReport& report) {
  const auto& req = report.request;
  const auto& p = report.prepared;
  std::string out;
  out += format("estimate   %s (%zu poses)\n", req.est_file.c_str(), p.num_est_loaded);
  out += format("reference  %s (%zu poses, format %s)\n", req.ref_file.c_str(), p.num_ref_loaded,
                std::string(trajectory_format_name(req.ref_format)).c_str());
  if (p.association)
    out += format("matched    %zu poses (t_max_diff %g s, t_offset %g s)\n", p.association->size(),
                  req.options.association.t_max_diff, req.options.association.t_offset);
  else
    out += format("matched    %zu poses (paired by index: no timestamps)\n", p.ref.size());
  if (p.alignment) {
    const auto& a = *p.alignment;
    const auto& T = a.transform;
    out += format("alignment  %s (Umeyama) fitted on %zu poses\n",
                  std::string(align_mode_name(a.applied)).c_str(), a.n_used);
    if (a.applied != AlignMode::scale_only) {
      out += format("  rotation     %.3f deg\n", geometry::rotation_angle(T.rotation) * 180.0 / std::numbers::pi);
      out += format("  translation  [%.6f, %.6f, %.6f] m\n", T.translation.x(), T.translation.y(), T.translation.z());
    }
    if (a.applied != AlignMode::se3) out += format("  scale        %.6f (Sim3)\n", T.scale);
  } else if (!p.origin_alignment) {
    out += "alignment  none\n";
  }
  if (p.origin_alignment)
    out += format("alignment  origin: estimate's first pose moved onto the reference's (t = [%.6f, %.6f, %.6f] m)\n",
                  p.origin_alignment->translation().x(), p.origin_alignment->translation().y(),
                  p.origin_alignment->translation().z());
  out += "\n";
  int relation_width = 8;
  for (const auto& r : report.results)
    relation_width = std::max(relation_width, static_cast<int>(pose_relation_name(r.relation).size()));
  out += format("%-6s %-*s %-9s %6s %10s %10s %10s %10s %10s %10s %10s\n", "metric", relation_width, "relation",
                "unit", "n", "rmse", "mean", "median", "std", "min", "max", "sse");
  for (const auto& r : report.results) {
    const auto& s = r.stats;
    out += format("%-6s %-*s %-9s %6zu %10.5g %10.5g %10.5g %10.5g %10.5g %10.5g %10.5g\n",
                  metric_name(r.metric).c_str(), relation_width, std::string(pose_relation_name(r.relation)).c_str(),
                  std::string(unit_name(r.relation)).c_str(), r.errors.size(), s.rmse, s.mean, s.median, s.std,
                  s.min, s.max, s.sse);
  }
  for (const auto& r : report.results)
    if (r.metric == Metric::rpe) {
      out += format("\nRPE: %zu pose pairs, delta %s, selected on the %s\n", r.pairs.size(),
                    delta_text(req.options.rpe).c_str(), req.options.pairs_from_reference ? "reference" : "estimate");
      break;
    }
  return out;
}

nlohmann::json report_to_json(const EvalReport& report) {
  const auto& req = report.request;
  const auto& p = report.prepared;
  const auto& o = req.options;
  nlohmann::json j;
  j["estimate"] = {{"file", req.est_file.string()}, {"poses_loaded", p.num_est_loaded}};
  j["reference"] = {{"file", req.ref_file.string()},
                    {"poses_loaded", p.num_ref_loaded},
                    {"format", std::string(trajectory_format_name(req.ref_format))}};
  j["options"] = {{"t_max_diff", o.association.t_max_diff},
                  {"t_offset", o.association.t_offset},
                  {"align", std::string(align_mode_name(o.align))},
                  {"n_to_align", o.n_to_align},
                  {"align_origin", o.align_origin},
                  {"delta", o.rpe.delta},
                  {"delta_unit", std::string(delta_unit_name(o.rpe.unit))},
                  {"delta_tol", o.rpe.delta_tol},
                  {"all_pairs", o.rpe.all_pairs},
                  {"pairs_from_reference", o.pairs_from_reference}};
  j["num_compared_poses"] = p.ref.size();
  if (p.association)
    j["association"] = {{"num_matches", p.association->size()},
                        {"est_longer_than_ref", p.association->est_longer_than_ref}};
  else
    j["association"] = nullptr;
  if (p.alignment)
    j["alignment"] = {{"applied", std::string(align_mode_name(p.alignment->applied))},
                      {"rotation", matrix_json(p.alignment->transform.rotation)},
                      {"translation", matrix_json(p.alignment->transform.translation.transpose())[0]},
                      {"scale", p.alignment->transform.scale},
                      {"n_used", p.alignment->n_used}};
  else
    j["alignment"] = nullptr;
  j["origin_alignment"] = p.origin_alignment ? matrix_json(p.origin_alignment->matrix()) : nlohmann::json(nullptr);
  auto results = nlohmann::json::array();
  for (const auto& r : report.results) {
    nlohmann::json rj = {{"metric", r.metric == Metric::ape ? "ape" : "rpe"},
                         {"relation", std::string(pose_relation_name(r.relation))},
                         {"unit", std::string(unit_name(r.relation))},
                         {"num_errors", r.errors.size()},
                         {"stats", stats_json(r.stats)}};
    if (r.metric == Metric::rpe) rj["num_pairs"] = r.pairs.size();
    results.push_back(rj);
  }
  j["results"] = results;
  return j;
}

void check_output_folder(const fs::path& file) {
  if (file.has_parent_path() && !fs::is_directory(file.parent_path()))
    throw InputError(file, "cannot write: folder " + file.parent_path().string() + " does not exist");
}

void write_json_file(const nlohmann::json& json, const fs::path& file) {
  check_output_folder(file);
  const fs::path tmp = file.string() + ".tmp" + std::to_string(::getpid());
  {
    std::ofstream out(tmp);
    out << json.dump(2) << '\n';
    out.close();
    if (!out) {
      std::error_code ec;
      fs::remove(tmp, ec);
      throw InputError(file, "cannot write");
    }
  }
  std::error_code ec;
  fs::rename(tmp, file, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw InputError(file, "cannot write: " + ec.message());
  }
}

}  // namespace pllvo::eval
