#include "pllvo/eval/association.h"

#include <algorithm>
#include <cmath>

#include "pllvo/eval/eval_error.h"
#include "pllvo/eval/nearest_index.h"

namespace pllvo::eval {

namespace {

/// evo's argmin over |shifted_j - target| (first index on ties), by full scan.
size_t nearest_by_scan(const std::vector<double>& shifted, double target) {
  size_t best = 0;
  for (size_t j = 1; j < shifted.size(); ++j)
    if (std::abs(shifted[j] - target) < std::abs(shifted[best] - target)) best = j;
  return best;
}

}  // namespace

Association associate(const std::vector<double>& ref_stamps, const std::vector<double>& est_stamps,
                      const AssociationOptions& options) {
  Association out;
  out.est_longer_than_ref = est_stamps.size() > ref_stamps.size();
  const auto& short_stamps = out.est_longer_than_ref ? ref_stamps : est_stamps;
  const auto& long_stamps = out.est_longer_than_ref ? est_stamps : ref_stamps;
  // The offset always moves the estimate: +offset on the long side when that is the estimate.
  // Shift first, subtract second: the same rounding as evo.
  const double long_shift = out.est_longer_than_ref ? options.t_offset : -options.t_offset;
  std::vector<double> shifted(long_stamps.size());
  for (size_t j = 0; j < long_stamps.size(); ++j) shifted[j] = long_stamps[j] + long_shift;
  const bool sorted = std::is_sorted(shifted.begin(), shifted.end());

  for (size_t i = 0; i < short_stamps.size() && !shifted.empty(); ++i) {
    const size_t j = sorted ? detail::nearest_index_sorted(0, shifted.size(), short_stamps[i],
                                                           [&](size_t k) { return shifted[k]; })
                            : nearest_by_scan(shifted, short_stamps[i]);
    if (!(std::abs(shifted[j] - short_stamps[i]) <= options.t_max_diff)) continue;
    out.ref_indices.push_back(out.est_longer_than_ref ? i : j);
    out.est_indices.push_back(out.est_longer_than_ref ? j : i);
  }
  if (out.size() == 0)
    throw EvalError(EvalErrorKind::sync,
                    "found no matching timestamps between reference and estimate with max. time diff " +
                        python_repr(options.t_max_diff) + " (s) and time offset " +
                        python_repr(options.t_offset) + " (s)");
  return out;
}

}  // namespace pllvo::eval
