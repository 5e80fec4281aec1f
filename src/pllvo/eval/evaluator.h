#pragma once
// evo's evaluation order on two loaded trajectories: associate (timestamped inputs only)
// -> align (Umeyama) or align to the origin -> APE / RPE -> statistics.
#include <optional>
#include <vector>

#include <Eigen/Geometry>

#include "pllvo/common/yaml_config.h"
#include "pllvo/eval/alignment.h"
#include "pllvo/eval/association.h"
#include "pllvo/eval/metrics.h"
#include "pllvo/eval/pair_selection.h"
#include "pllvo/eval/statistics.h"
#include "pllvo/io/trajectory.h"

namespace pllvo::eval {

/// Defaults are evo's defaults, except min_poses (evo needs only one associated pose).
struct EvalOptions {
  AssociationOptions association;
  AlignMode align = AlignMode::none;
  long n_to_align = -1;               ///< fit the alignment on the first N poses; -1: all
  bool align_origin = false;          ///< est <- ref[0] * est[0]^-1 * est (not with se3/sim3)
  PairOptions rpe;                    ///< RPE pair selection
  bool pairs_from_reference = false;  ///< select RPE pairs on the reference instead of the estimate
  size_t min_poses = 3;               ///< fewer poses to compare is an input error
  bool allow_collinear = false;       ///< align onto a straight-line reference (evo refuses; see umeyama)

  /// Keys: t_max_diff, t_offset, align (none|se3|sim3|scale), n_to_align, align_origin, delta,
  /// delta_unit (frames|m|deg|rad), delta_tol, all_pairs, pairs_from_reference, min_poses,
  /// allow_collinear.
  void load(const ConfigNode& node);
  /// InputError for contradictory or out-of-range values.
  void validate() const;
};

/// The two trajectories reduced to compared poses, the estimate aligned onto the reference.
struct PreparedTrajectories {
  PoseList ref;
  PoseList est;
  size_t num_ref_loaded = 0;
  size_t num_est_loaded = 0;
  std::optional<Association> association;  ///< timestamped inputs only (KITTI pairs by index)
  std::optional<Alignment> alignment;
  std::optional<Eigen::Isometry3d> origin_alignment;
};

enum class Metric { ape, rpe };

struct MetricResult {
  Metric metric = Metric::ape;
  PoseRelation relation = PoseRelation::trans_part;
  std::vector<double> errors;
  IdPairs pairs;  ///< RPE: the compared index pairs (indices into PreparedTrajectories)
  Statistics stats;
};

class Evaluator {
 public:
  explicit Evaluator(EvalOptions options);  ///< validates the options

  /// Associates (or pairs KITTI poses by index) and aligns. Throws EvalError for evo's errors
  /// and InputError when fewer than min_poses poses remain.
  PreparedTrajectories prepare(const io::Trajectory& ref, const io::Trajectory& est) const;
  MetricResult ape(const PreparedTrajectories& prepared, PoseRelation relation) const;
  MetricResult rpe(const PreparedTrajectories& prepared, PoseRelation relation) const;

  const EvalOptions& options() const { return options_; }

 private:
  EvalOptions options_;
};

}  // namespace pllvo::eval
