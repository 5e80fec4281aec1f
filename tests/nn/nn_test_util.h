#pragma once
// Helpers shared by the nn tests: fixture paths, comparisons with the reference vectors.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sys/wait.h>
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

/// A Python 3 with torch and numpy: $PLLVO_PYTHON, else /usr/bin/python3 (Debian's
/// python3-torch), else python3 on PATH. Empty when none imports torch.
inline std::string find_python_with_torch() {
  std::vector<std::string> candidates;
  if (const char* env = std::getenv("PLLVO_PYTHON"); env && *env) candidates.emplace_back(env);
  candidates.insert(candidates.end(), {"/usr/bin/python3", "python3"});
  for (const auto& py : candidates)
    if (std::system((py + " -c 'import torch, numpy' >/dev/null 2>&1").c_str()) == 0) return py;
  return "";
}
inline const std::string& python_with_torch() {
  static const std::string python = find_python_with_torch();
  return python;
}

/// Runs a shell command, returns its exit status and (stdout + stderr) in `output`.
inline int run_command(const std::string& command, std::string& output) {
  output.clear();
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return -1;
  char buf[4096];
  while (std::size_t n = std::fread(buf, 1, sizeof buf, pipe)) output.append(buf, n);
  const int status = pclose(pipe);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/// "1.23e-05": for RecordProperty (std::to_string rounds small errors to 0.000000).
inline std::string sci(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

}  // namespace pllvo::nn::test
