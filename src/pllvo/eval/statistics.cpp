#include "pllvo/eval/statistics.h"

#include <algorithm>
#include <cmath>

#include "pllvo/common/error.h"

namespace pllvo::eval {

Statistics compute_statistics(const std::vector<double>& errors) {
  if (errors.empty()) throw InternalError("compute_statistics: empty error array");
  const double n = static_cast<double>(errors.size());
  Statistics s;
  double sum = 0.0;
  for (const double e : errors) {
    sum += e;
    s.sse += e * e;
  }
  s.mean = sum / n;
  s.rmse = std::sqrt(s.sse / n);
  double var = 0.0;
  for (const double e : errors) var += (e - s.mean) * (e - s.mean);
  s.std = std::sqrt(var / n);
  const auto [lo, hi] = std::minmax_element(errors.begin(), errors.end());
  s.min = *lo;
  s.max = *hi;
  std::vector<double> sorted = errors;
  std::sort(sorted.begin(), sorted.end());
  const size_t m = sorted.size() / 2;
  s.median = sorted.size() % 2 ? sorted[m] : 0.5 * (sorted[m - 1] + sorted[m]);
  return s;
}

}  // namespace pllvo::eval
