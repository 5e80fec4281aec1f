#pragma once
// Time association of an estimate with a reference, as evo's associate_trajectories.
#include <cstddef>
#include <vector>

namespace pllvo::eval {

struct AssociationOptions {
  double t_max_diff = 0.01;  ///< s; a pair is kept when |difference| <= t_max_diff (evo default)
  double t_offset = 0.0;     ///< s; added to the estimate's stamps: est + t_offset ~ ref
};

/// Matched pairs in the order of the shorter trajectory: ref_indices[k] <-> est_indices[k]
/// (0-based indices into the loaded trajectories).
struct Association {
  std::vector<size_t> ref_indices;
  std::vector<size_t> est_indices;
  bool est_longer_than_ref = false;  ///< which side was searched (the longer one)

  size_t size() const { return ref_indices.size(); }
};

/// evo's rule: every stamp of the shorter trajectory (the estimate on equal length) takes
/// the nearest stamp of the longer one (first index on ties), kept when within t_max_diff.
/// Long-side stamps may be used more than once. Throws EvalError(sync) on zero matches.
Association associate(const std::vector<double>& ref_stamps, const std::vector<double>& est_stamps,
                      const AssociationOptions& options);

}  // namespace pllvo::eval
