#pragma once
// Which pose pairs the RPE compares, as evo's id_pairs_from_delta.
#include <string_view>
#include <utility>
#include <vector>

#include "pllvo/eval/pose_list.h"

namespace pllvo::eval {

enum class DeltaUnit { frames, meters, degrees, radians };

DeltaUnit parse_delta_unit(std::string_view name);   ///< frames|f, m|meters, deg|d|degrees, rad|r|radians
std::string_view delta_unit_name(DeltaUnit unit);    ///< evo's names: frames, m, deg, rad

struct PairOptions {
  double delta = 1.0;                  ///< evo default: 1 frame
  DeltaUnit unit = DeltaUnit::frames;
  double delta_tol = 0.1;              ///< relative tolerance for all_pairs in m/deg/rad (evo default)
  bool all_pairs = false;              ///< every start index instead of consecutive, non-overlapping pairs
};

using IdPairs = std::vector<std::pair<size_t, size_t>>;

/// Index pairs (i, j), i < j, selected on `poses` (evo: the aligned estimate, or the reference
/// with pairs_from_reference). Frames: (0,d),(d,2d),... or (i,i+d). Metres: path length,
/// consecutive pairs start where the path first reaches delta. Angles: accumulated (consecutive)
/// or direct (all pairs) rotation angle. Throws EvalError(filter) when no pair is found and
/// InputError for an invalid delta.
IdPairs select_pairs(const PoseList& poses, const PairOptions& options);

}  // namespace pllvo::eval
