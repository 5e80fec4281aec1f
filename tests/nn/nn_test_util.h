#pragma once
// Helpers shared by the nn tests: fixture paths, comparisons with the reference vectors.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "pllvo/common/fixtures.h"
#include "pllvo/nn/safetensors.h"

namespace pllvo::nn::test {

inline std::filesystem::path superpoint_vector(const std::string& name) {
  return shared_path("testvectors/superpoint/" + name);
}
inline std::filesystem::path lightglue_vector(const std::string& name) {
  return shared_path("testvectors/lightglue/" + name);
}

/// max |a - b| over equally sized ranges (infinity when the sizes differ).
template <typename A, typename B>
double max_abs_diff_n(const A& a, const B& b, std::size_t n) {
  double m = 0;
  for (std::size_t i = 0; i < n; ++i) m = std::max(m, std::abs(static_cast<double>(a[i]) - static_cast<double>(b[i])));
  return m;
}

inline double max_abs_diff(const std::vector<float>& ref, const float* ours, std::size_t n) {
  if (ref.size() != n) return INFINITY;
  return max_abs_diff_n(ref, ours, n);
}

/// "1.23e-05": for RecordProperty (std::to_string rounds small errors to 0.000000).
inline std::string sci(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

}  // namespace pllvo::nn::test
