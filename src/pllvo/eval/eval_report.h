#pragma once
// One `pllvo eval` run: load both files, evaluate, and present the result as a table for
// people and as JSON for scripts.
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "pllvo/eval/evaluator.h"
#include "pllvo/eval/trajectory_input.h"

namespace pllvo::eval {

struct EvalRequest {
  std::filesystem::path est_file;
  std::filesystem::path ref_file;
  TrajectoryFormat ref_format = TrajectoryFormat::automatic;
  EvalOptions options;
  std::vector<Metric> metrics{Metric::ape, Metric::rpe};
  std::vector<PoseRelation> relations{PoseRelation::trans_part, PoseRelation::angle_deg};
};

struct EvalReport {
  EvalRequest request;
  PreparedTrajectories prepared;
  std::vector<MetricResult> results;  ///< metrics x relations, in request order
};

/// "ape", "rpe" or "both" (the CLI's --metric); InputError for another name.
std::vector<Metric> parse_metrics(const std::string& name);

/// Loads, associates, aligns and computes every requested metric and relation. Every error is
/// an InputError naming the file at fault (evaluation errors name the estimate and reference).
EvalReport run_evaluation(const EvalRequest& request);

/// Human-readable summary: inputs, matched poses, alignment (with the Sim(3) scale), stats.
std::string format_report(const EvalReport& report);

nlohmann::json report_to_json(const EvalReport& report);

/// InputError naming `file` when its folder does not exist (checked before a long run).
void check_output_folder(const std::filesystem::path& file);

/// Writes to a temporary file beside `file` and renames it, so a reader never sees half a file.
void write_json_file(const nlohmann::json& json, const std::filesystem::path& file);

}  // namespace pllvo::eval
