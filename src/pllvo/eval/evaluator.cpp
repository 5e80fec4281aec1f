#include "pllvo/eval/evaluator.h"

#include <cmath>
#include <numbers>
#include <string>

#include "pllvo/common/error.h"
#include "pllvo/eval/eval_error.h"

namespace pllvo::eval {

void EvalOptions::load(const ConfigNode& node) {
  node.get("t_max_diff", association.t_max_diff);
  node.get("t_offset", association.t_offset);
  std::string text(align_mode_name(align));
  node.get("align", text);
  try {
    align = parse_align_mode(text);
  } catch (const InputError& e) {
    throw InputError(node.file(), node.path("align"), e.what());
  }
  node.get("n_to_align", n_to_align);
  node.get("align_origin", align_origin);
  node.get("delta", rpe.delta);
  text = std::string(delta_unit_name(rpe.unit));
  node.get("delta_unit", text);
  try {
    rpe.unit = parse_delta_unit(text);
  } catch (const InputError& e) {
    throw InputError(node.file(), node.path("delta_unit"), e.what());
  }
  node.get("delta_tol", rpe.delta_tol);
  node.get("all_pairs", rpe.all_pairs);
  node.get("pairs_from_reference", pairs_from_reference);
  node.get("min_poses", min_poses);
  node.get("allow_collinear", allow_collinear);
  node.reject_unknown_keys();
}

void EvalOptions::validate() const {
  if (!(association.t_max_diff >= 0.0) || !std::isfinite(association.t_max_diff))
    throw InputError("t_max_diff must be a finite number >= 0 (s)");
  if (!std::isfinite(association.t_offset)) throw InputError("t_offset must be finite (s)");
  if (n_to_align == 0 || n_to_align < -1) throw InputError("n_to_align must be positive, or -1 for all poses");
  if (align_origin && (align == AlignMode::se3 || align == AlignMode::sim3))
    throw InputError("align_origin cannot be combined with se3/sim3 alignment (only with scale)");
  if (!(rpe.delta > 0.0) || !std::isfinite(rpe.delta)) throw InputError("the RPE delta must be a positive number");
  if (rpe.unit == DeltaUnit::frames && rpe.delta != std::floor(rpe.delta))
    throw InputError("the RPE delta in frames must be an integer");
  if (rpe.unit == DeltaUnit::degrees && rpe.delta > 180.0)
    throw InputError("the RPE delta angle must be within [0, 180] deg");
  if (rpe.unit == DeltaUnit::radians && rpe.delta > std::numbers::pi)
    throw InputError("the RPE delta angle must be within [0, pi] rad");
  if (!(rpe.delta_tol >= 0.0)) throw InputError("the RPE delta tolerance must not be negative");
}

Evaluator::Evaluator(EvalOptions options) : options_(std::move(options)) { options_.validate(); }

PreparedTrajectories Evaluator::prepare(const io::Trajectory& ref, const io::Trajectory& est) const {
  PreparedTrajectories out;
  out.num_ref_loaded = ref.size();
  out.num_est_loaded = est.size();
  if (ref.empty() || est.empty()) throw InputError("empty trajectory: nothing to compare");
  if (ref.has_stamps() && est.has_stamps()) {
    out.association = associate(ref.stamps, est.stamps, options_.association);
    for (size_t k = 0; k < out.association->size(); ++k) {
      out.ref.push_back(ref.poses[out.association->ref_indices[k]]);
      out.est.push_back(est.poses[out.association->est_indices[k]]);
    }
  } else if (!ref.has_stamps() && !est.has_stamps()) {
    if (ref.size() != est.size())
      throw InputError("trajectories without timestamps (KITTI) must have the same number of poses: reference " +
                       std::to_string(ref.size()) + ", estimate " + std::to_string(est.size()));
    out.ref = ref.poses;
    out.est = est.poses;
  } else {
    throw InputError(std::string("cannot associate: the ") + (ref.has_stamps() ? "estimate" : "reference") +
                     " has no timestamps (KITTI) but the other file has: both must be timestamped, or both KITTI");
  }
  if (out.ref.size() < options_.min_poses) {
    const auto& a = options_.association;
    throw InputError("only " + std::to_string(out.ref.size()) + " pose(s) to compare, at least " +
                     std::to_string(options_.min_poses) + " are needed" +
                     (out.association ? " (poses associated within t_max_diff " + python_repr(a.t_max_diff) +
                                            " s, t_offset " + python_repr(a.t_offset) + " s)"
                                      : std::string()));
  }
  if (options_.align != AlignMode::none)
    out.alignment = align(out.est, out.ref, options_.align, options_.n_to_align, options_.allow_collinear);
  if (options_.align_origin) out.origin_alignment = align_origin(out.est, out.ref);
  return out;
}

MetricResult Evaluator::ape(const PreparedTrajectories& prepared, PoseRelation relation) const {
  MetricResult r;
  r.metric = Metric::ape;
  r.relation = relation;
  r.errors = ape_errors(prepared.ref, prepared.est, relation);
  r.stats = compute_statistics(r.errors);
  return r;
}

MetricResult Evaluator::rpe(const PreparedTrajectories& prepared, PoseRelation relation) const {
  MetricResult r;
  r.metric = Metric::rpe;
  r.relation = relation;
  r.pairs = select_pairs(options_.pairs_from_reference ? prepared.ref : prepared.est, options_.rpe);
  r.errors = rpe_errors(prepared.ref, prepared.est, r.pairs, relation);
  if (r.errors.empty())
    throw EvalError(EvalErrorKind::metrics, "no RPE pair has a non-zero reference distance");
  r.stats = compute_statistics(r.errors);
  return r;
}

}  // namespace pllvo::eval
