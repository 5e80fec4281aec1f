#include "pllvo/nn/mnn_matcher.h"

#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include <ATen/Parallel.h>
#include <ATen/core/Tensor.h>
#include <ATen/ops/empty.h>
#include <ATen/ops/mm.h>
#include <c10/core/InferenceMode.h>

#include "pllvo/common/error.h"

namespace pllvo::nn {

MnnConfig MnnConfig::from_yaml(const ConfigNode& node) {
  MnnConfig c;
  node.get("mutual", c.mutual);
  node.get("ratio_threshold", c.ratio_threshold);
  node.get("distance_threshold", c.distance_threshold);
  node.reject_unknown_keys();
  if (c.ratio_threshold > 1.0f) throw InputError(node.file(), node.path("ratio_threshold"), "must be <= 1");
  return c;
}

namespace {

at::Tensor as_tensor(const DescriptorMatrix& d) {
  at::Tensor t = at::empty({d.rows(), d.cols()}, at::TensorOptions().dtype(at::kFloat));
  if (d.size() > 0) std::memcpy(t.data_ptr<float>(), d.data(), sizeof(float) * static_cast<std::size_t>(d.size()));
  return t;
}

}  // namespace

Matches match_mutual_nearest(const Features& f0, const Features& f1, const MnnConfig& config) {
  Matches out;
  const auto m = f0.descriptors.rows(), n = f1.descriptors.rows();
  if (m == 0 || n == 0) {
    out.pairs.resize(0, 2);
    return out;
  }
  if (f0.descriptors.cols() != f1.descriptors.cols())
    throw InputError("mutual nearest neighbours: descriptor sizes differ (" + std::to_string(f0.descriptors.cols()) +
                     " vs " + std::to_string(f1.descriptors.cols()) + ")");
  c10::InferenceMode guard;
  const at::Tensor sim_t = at::mm(as_tensor(f0.descriptors), as_tensor(f1.descriptors).t()).contiguous();
  const float* sim = sim_t.data_ptr<float>();

  // Best and second best per row (rows in parallel), best per column (first index wins ties).
  constexpr float lowest = -std::numeric_limits<float>::infinity();
  std::vector<float> best(m, lowest), second(m, lowest);
  std::vector<int> best_j(m, 0);
  at::parallel_for(0, m, 64, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t i = begin; i < end; ++i) {
      const float* row = sim + i * n;
      for (Eigen::Index j = 0; j < n; ++j) {
        const float s = row[j];
        if (s > best[i]) {
          second[i] = best[i];
          best[i] = s;
          best_j[i] = static_cast<int>(j);
        } else if (s > second[i]) {
          second[i] = s;
        }
      }
    }
  });
  std::vector<float> col_best(n, lowest);
  std::vector<int> col_best_i(n, 0);
  for (Eigen::Index i = 0; i < m; ++i) {
    const float* row = sim + i * n;
    for (Eigen::Index j = 0; j < n; ++j)
      if (row[j] > col_best[j]) col_best[j] = row[j], col_best_i[j] = static_cast<int>(i);
  }
  const auto squared_distance = [](float s) { return 2.0f * (1.0f - s); };
  const float ratio2 = config.ratio_threshold * config.ratio_threshold;
  const float dist2 = config.distance_threshold * config.distance_threshold;
  std::vector<std::pair<int, int>> pairs;
  std::vector<float> scores;
  for (Eigen::Index i = 0; i < m; ++i) {
    const int j = best_j[i];
    if (config.mutual && col_best_i[j] != i) continue;
    if (config.ratio_threshold > 0.0f && n > 1 && !(squared_distance(best[i]) <= ratio2 * squared_distance(second[i]))) continue;
    if (config.distance_threshold > 0.0f && !(squared_distance(best[i]) <= dist2)) continue;
    pairs.emplace_back(static_cast<int>(i), j);
    scores.push_back(best[i]);
  }
  out.pairs.resize(static_cast<Eigen::Index>(pairs.size()), 2);
  out.scores.resize(static_cast<Eigen::Index>(pairs.size()));
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    out.pairs(k, 0) = pairs[k].first;
    out.pairs(k, 1) = pairs[k].second;
    out.scores(k) = scores[k];
  }
  return out;
}

}  // namespace pllvo::nn
