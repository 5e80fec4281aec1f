#include "pllvo/vo/trajectory_error.h"

#include <spdlog/spdlog.h>

#include "pllvo/eval/eval_error.h"
#include "pllvo/eval/evaluator.h"

namespace pllvo::vo {
namespace {

TrajectoryError evaluate(const io::Trajectory& estimate, const io::Trajectory& reference, bool metric_scale,
                         bool allow_collinear) {
  eval::EvalOptions options;
  options.align = metric_scale ? eval::AlignMode::se3 : eval::AlignMode::sim3;
  options.allow_collinear = allow_collinear;
  const eval::Evaluator evaluator(options);
  const auto prepared = evaluator.prepare(reference, estimate);
  const auto ape = evaluator.ape(prepared, eval::PoseRelation::trans_part);
  TrajectoryError e;
  e.align = metric_scale ? "se3" : "sim3";
  e.collinear_reference = allow_collinear;
  e.matched_poses = prepared.ref.size();
  e.rmse_m = ape.stats.rmse;
  e.max_m = ape.stats.max;
  for (size_t i = 1; i < prepared.ref.size(); ++i)
    e.path_length_m += (prepared.ref[i].translation() - prepared.ref[i - 1].translation()).norm();
  e.percent_of_path = e.path_length_m > 0 ? 100.0 * e.rmse_m / e.path_length_m : 0.0;
  if (prepared.alignment) e.scale = prepared.alignment->transform.scale;
  return e;
}

}  // namespace

std::optional<TrajectoryError> trajectory_error(const io::Trajectory& estimate, const io::Trajectory& reference,
                                                bool metric_scale) {
  if (estimate.size() < 3 || reference.size() < 3 || !reference.has_stamps()) return std::nullopt;
  try {
    try {
      return evaluate(estimate, reference, metric_scale, false);
    } catch (const eval::EvalError& ex) {
      if (ex.kind() != eval::EvalErrorKind::geometry) throw;
      // evo refuses a straight-line reference (rank-1 covariance); the least-squares fit still
      // exists, only the rotation about the line is arbitrary, which the APE does not depend on.
      auto e = evaluate(estimate, reference, metric_scale, true);
      spdlog::info("ground truth is a straight line: {} alignment with the rotation about it unobservable", e.align);
      return e;
    }
  } catch (const std::exception& ex) {
    // Too few matched stamps or a degenerate alignment: no error to report, not a failure.
    spdlog::warn("trajectory error not computed: {}", ex.what());
    return std::nullopt;
  }
}

}  // namespace pllvo::vo
