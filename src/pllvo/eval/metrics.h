#pragma once
// Absolute and relative pose errors, as evo's metrics.APE and metrics.RPE.
#include <string_view>
#include <vector>

#include "pllvo/eval/pair_selection.h"
#include "pllvo/eval/pose_list.h"

namespace pllvo::eval {

/// evo's pose relations, with evo's CLI names.
enum class PoseRelation {
  trans_part,                  ///< translation error, m
  rot_part,                    ///< |R(E) - I|_F, unit-less (not an angle)
  full,                        ///< |E - I4|_F, unit-less
  angle_deg,                   ///< rotation angle of E in [0, 180] deg
  angle_rad,                   ///< rotation angle of E in [0, pi] rad
  point_distance,              ///< APE: position distance; RPE: difference of pair distances, m
  point_distance_error_ratio,  ///< RPE only: point_distance / reference pair distance * 100, %
};

PoseRelation parse_pose_relation(std::string_view name);  ///< InputError on an unknown name
std::string_view pose_relation_name(PoseRelation relation);
std::string_view unit_name(PoseRelation relation);  ///< m, deg, rad, unit-less, %

/// Per-pose errors of index-matched poses; E_i = est_i^-1 * ref_i for the rotation relations.
std::vector<double> ape_errors(const PoseList& ref, const PoseList& est, PoseRelation relation);

/// Per-pair errors, E = (Q_i^-1 Q_j)^-1 (P_i^-1 P_j) with Q the reference and P the estimate.
/// point_distance_error_ratio skips pairs whose reference distance is zero.
std::vector<double> rpe_errors(const PoseList& ref, const PoseList& est, const IdPairs& pairs,
                               PoseRelation relation);

}  // namespace pllvo::eval
