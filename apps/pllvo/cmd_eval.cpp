// pllvo eval EST REF: evo-exact trajectory evaluation (APE/RPE). Argument order is
// estimate first, reference second (evo's own order is REF EST).
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "commands.h"
#include "pllvo/common/yaml_config.h"
#include "pllvo/eval/eval_report.h"

namespace pllvo::cli {

namespace {

struct EvalArgs {
  std::string est, ref, ref_format = "auto", metric = "both", align = "none", delta_unit = "frames";
  std::vector<std::string> relations{"trans_part", "angle_deg"};
  std::string json, config;
  eval::EvalOptions defaults;  // only to print the defaults in --help
  long n_to_align = -1;
  double t_max_diff = defaults.association.t_max_diff, t_offset = defaults.association.t_offset;
  double delta = defaults.rpe.delta, delta_tol = defaults.rpe.delta_tol;
  bool align_origin = false, all_pairs = false, pairs_from_reference = false;
};

/// Config file first (when given), then every option given on the command line.
eval::EvalOptions options_from(const EvalArgs& a, const CLI::App& cmd) {
  eval::EvalOptions o;
  if (!a.config.empty()) o.load(ConfigNode::load_file(a.config));
  auto given = [&](const char* name) { return cmd.get_option(name)->count() > 0; };
  if (given("--t-max-diff")) o.association.t_max_diff = a.t_max_diff;
  if (given("--t-offset")) o.association.t_offset = a.t_offset;
  if (given("--align")) o.align = eval::parse_align_mode(a.align);
  if (given("--n-to-align")) o.n_to_align = a.n_to_align;
  if (given("--align-origin")) o.align_origin = true;
  if (given("--delta")) o.rpe.delta = a.delta;
  if (given("--delta-unit")) o.rpe.unit = eval::parse_delta_unit(a.delta_unit);
  if (given("--delta-tol")) o.rpe.delta_tol = a.delta_tol;
  if (given("--all-pairs")) o.rpe.all_pairs = true;
  if (given("--pairs-from-reference")) o.pairs_from_reference = true;
  return o;
}

}  // namespace

void add_eval_command(CLI::App& app) {
  auto args = std::make_shared<EvalArgs>();
  auto* cmd = app.add_subcommand(
      "eval", "compare an estimated trajectory with a reference, evo-exact (APE/RPE): pllvo eval EST REF");
  cmd->footer(
      "ARGUMENT ORDER: pllvo eval EST REF -- the estimate first, the reference second.\n"
      "evo's own commands take them the other way round (evo_ape tum REF EST).\n\n"
      "Order of operations, as evo: load -> associate by timestamp (TUM/EuRoC; pairs by index for\n"
      "KITTI) -> --align, or --align-origin -> APE/RPE -> statistics (rmse, mean, median, std, min,\n"
      "max, sse). Fewer than 3 poses to compare is an error.\n\n"
      "Example: pllvo eval est.tum ref.tum --align se3 --json results.json");
  cmd->add_option("EST", args->est, "estimated trajectory (TUM: t tx ty tz qx qy qz qw; or KITTI)")->required();
  cmd->add_option("REF", args->ref, "reference trajectory (TUM, EuRoC ground-truth csv or KITTI)")->required();
  cmd->add_option("--ref-format", args->ref_format,
                  "tum | euroc (EuRoC csv reference, TUM estimate) | kitti (both, no timestamps) | auto "
                  "(each file by its content)")
      ->capture_default_str();
  cmd->add_option("--metric", args->metric, "ape | rpe | both")->capture_default_str();
  cmd->add_option("--relation", args->relations,
                  "pose relation(s), evo's names: trans_part, rot_part, full, angle_deg, angle_rad, "
                  "point_distance, point_distance_error_ratio (RPE only); comma-separated or repeated")
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_option("--align", args->align,
                  "none | se3 (evo -a) | sim3 (evo -a -s, prints the scale) | scale (evo -s: scale only)")
      ->capture_default_str();
  cmd->add_option("--n-to-align", args->n_to_align, "fit the alignment on the first N matched poses (-1: all)")
      ->capture_default_str();
  cmd->add_flag("--align-origin", args->align_origin,
                "move the estimate's first pose onto the reference's (not with se3/sim3; with scale it comes after)");
  cmd->add_option("--t-max-diff", args->t_max_diff, "max. time difference of associated stamps, s")
      ->capture_default_str();
  cmd->add_option("--t-offset", args->t_offset, "added to the estimate's stamps before association, s")
      ->capture_default_str();
  cmd->add_option("--delta", args->delta, "RPE: distance between the poses of a pair")->capture_default_str();
  cmd->add_option("--delta-unit", args->delta_unit, "RPE: frames | m (path length) | deg | rad (rotation angle)")
      ->capture_default_str();
  cmd->add_flag("--all-pairs", args->all_pairs, "RPE: a pair from every pose instead of consecutive pairs");
  cmd->add_flag("--pairs-from-reference", args->pairs_from_reference,
                "RPE: select the pairs on the reference instead of the aligned estimate");
  cmd->add_option("--delta-tol", args->delta_tol, "RPE, m/deg/rad with --all-pairs: relative tolerance on delta")
      ->capture_default_str();
  cmd->add_option("--config", args->config,
                  "YAML file with evaluation options (keys as config/eval.yaml); command-line options win");
  cmd->add_option("--json", args->json, "also write the results as JSON to this file");

  cmd->callback([args, cmd] {
    eval::EvalRequest request;
    request.est_file = args->est;
    request.ref_file = args->ref;
    request.ref_format = eval::parse_trajectory_format(args->ref_format);
    request.options = options_from(*args, *cmd);
    request.metrics = eval::parse_metrics(args->metric);
    request.relations.clear();
    for (const auto& r : args->relations) request.relations.push_back(eval::parse_pose_relation(r));

    if (!args->json.empty()) eval::check_output_folder(args->json);
    const auto report = eval::run_evaluation(request);
    std::fputs(eval::format_report(report).c_str(), stdout);
    if (!args->json.empty()) {
      eval::write_json_file(eval::report_to_json(report), args->json);
      std::fprintf(stderr, "pllvo: results written to %s\n", args->json.c_str());
    }
  });
}

}  // namespace pllvo::cli
