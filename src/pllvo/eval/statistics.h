#pragma once
// Summary statistics of an error array, as evo's PE.get_statistic.
#include <vector>

namespace pllvo::eval {

struct Statistics {
  double rmse = 0;    ///< sqrt(mean(e^2))
  double mean = 0;
  double median = 0;  ///< mean of the two middle values for an even count (np.median)
  double std = 0;     ///< population standard deviation (ddof = 0), as numpy's default
  double min = 0;
  double max = 0;
  double sse = 0;     ///< sum of e^2
};

/// InternalError on an empty array (the metrics never produce one: evo raises earlier).
Statistics compute_statistics(const std::vector<double>& errors);

}  // namespace pllvo::eval
