#include "pllvo/nn/adaptive_threshold.h"

#include <algorithm>
#include <cmath>
#include <functional>

#include "pllvo/common/error.h"
#include "pllvo/nn/superpoint.h"

namespace pllvo::nn {

AdaptiveThresholdConfig AdaptiveThresholdConfig::from_yaml(const ConfigNode& node) {
  AdaptiveThresholdConfig c;
  node.get("target_keypoints", c.target_keypoints);
  node.get("max_keypoints", c.max_keypoints);
  node.get("min_threshold", c.min_threshold);
  node.get("max_threshold", c.max_threshold);
  node.get("grid_cols", c.grid_cols);
  node.get("grid_rows", c.grid_rows);
  node.get("min_occupancy", c.min_occupancy);
  node.get("poor_matches", c.poor_matches);
  node.get("poor_ratio", c.poor_ratio);
  node.get("good_matches", c.good_matches);
  node.get("good_ratio", c.good_ratio);
  node.get("gain_step", c.gain_step);
  node.get("min_gain", c.min_gain);
  node.get("max_gain", c.max_gain);
  node.reject_unknown_keys();
  if (const auto [key, what] = c.problem(); !key.empty()) throw InputError(node.file(), node.path(key), what);
  return c;
}

std::pair<std::string, std::string> AdaptiveThresholdConfig::problem() const {
  if (target_keypoints <= 0) return {"target_keypoints", "must be > 0"};
  if (!(min_threshold >= 0.0f)) return {"min_threshold", "must be >= 0"};
  if (!(max_threshold >= min_threshold)) return {"max_threshold", "must be >= min_threshold"};
  if (grid_cols <= 0) return {"grid_cols", "must be > 0"};
  if (grid_rows <= 0) return {"grid_rows", "must be > 0"};
  if (!(min_occupancy >= 0.0f && min_occupancy <= 1.0f)) return {"min_occupancy", "must be in [0, 1]"};
  if (!(gain_step >= 1.0f)) return {"gain_step", "must be >= 1"};
  if (!(min_gain > 0.0f && min_gain <= 1.0f)) return {"min_gain", "must be in (0, 1]"};
  if (!(max_gain >= 1.0f)) return {"max_gain", "must be >= 1"};
  return {};
}

void AdaptiveThresholdConfig::validate() const {
  if (const auto [key, what] = problem(); !key.empty()) throw InputError("adaptive threshold setting " + key + ": " + what);
}

namespace {

int cell_of(const KeypointCandidates& c, std::size_t i, int cols, int rows) {
  const int cx = std::min(cols - 1, c.x[i] * cols / std::max(c.width, 1));
  const int cy = std::min(rows - 1, c.y[i] * rows / std::max(c.height, 1));
  return cy * cols + cx;
}

// The (k+1)-th largest value (0-based k) or `fallback` when there are no more than k values:
// keeping values > result leaves exactly k (no ties in practice).
float kth_largest(std::vector<float> values, std::size_t k, float fallback) {
  if (values.size() <= k) return fallback;
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end(), std::greater<>());
  return values[k];
}

}  // namespace

std::pair<float, int> grid_occupancy(const KeypointCandidates& c, const std::vector<std::int32_t>& selected,
                                     int grid_cols, int grid_rows, float floor) {
  std::vector<char> textured(static_cast<std::size_t>(grid_cols * grid_rows), 0), covered(textured.size(), 0);
  for (std::size_t i = 0; i < c.size(); ++i)
    if (c.score[i] > floor) textured[cell_of(c, i, grid_cols, grid_rows)] = 1;
  for (const auto i : selected) covered[cell_of(c, static_cast<std::size_t>(i), grid_cols, grid_rows)] = 1;
  int n_textured = 0, n_covered = 0;
  for (std::size_t k = 0; k < textured.size(); ++k) {
    n_textured += textured[k];
    n_covered += textured[k] && covered[k];
  }
  return {n_textured ? static_cast<float>(n_covered) / static_cast<float>(n_textured) : 1.0f, n_textured};
}

AdaptiveThreshold::AdaptiveThreshold(AdaptiveThresholdConfig config) : config_(config) { config_.validate(); }

int AdaptiveThreshold::target() const {
  return std::max(1, static_cast<int>(std::lround(static_cast<float>(config_.target_keypoints) * gain_)));
}

std::vector<std::int32_t> AdaptiveThreshold::select(const KeypointCandidates& c, ThresholdDecision* decision) const {
  const auto& cfg = config_;
  ThresholdDecision d;
  d.target = target();

  // Candidates above the noise floor, and the best score of each textured cell.
  std::vector<float> scores;
  std::vector<float> cell_best(static_cast<std::size_t>(cfg.grid_cols * cfg.grid_rows), -1.0f);
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (!(c.score[i] > cfg.min_threshold)) continue;
    scores.push_back(c.score[i]);
    auto& best = cell_best[cell_of(c, i, cfg.grid_cols, cfg.grid_rows)];
    best = std::max(best, c.score[i]);
  }
  std::vector<float> textured;
  for (const float b : cell_best)
    if (b > 0.0f) textured.push_back(b);
  d.textured_cells = static_cast<int>(textured.size());

  d.count_threshold = kth_largest(scores, static_cast<std::size_t>(d.target), cfg.min_threshold);
  const auto cells_needed = static_cast<std::size_t>(std::ceil(cfg.min_occupancy * static_cast<float>(textured.size())));
  d.coverage_threshold = kth_largest(textured, cells_needed, cfg.min_threshold);
  d.threshold = std::clamp(std::min(d.count_threshold, d.coverage_threshold), cfg.min_threshold, cfg.max_threshold);

  auto selected = select_keypoints(c, d.threshold, cfg.max_keypoints);
  d.selected = static_cast<int>(selected.size());
  d.occupancy = grid_occupancy(c, selected, cfg.grid_cols, cfg.grid_rows, cfg.min_threshold).first;
  if (decision) *decision = d;
  return selected;
}

Features AdaptiveThreshold::detect(const SuperPoint& superpoint, const cv::Mat& image, ThresholdDecision* decision) const {
  const auto dense = superpoint.run_network(image);
  const auto candidates = find_candidates(dense.scores, superpoint.config().nms_radius, superpoint.config().remove_borders);
  return extract_features(dense, candidates, select(candidates, decision));
}

void AdaptiveThreshold::report_matches(int matched, int keypoints) {
  const float ratio = keypoints > 0 ? static_cast<float>(matched) / static_cast<float>(keypoints) : 0.0f;
  if (matched < config_.poor_matches || ratio < config_.poor_ratio)
    gain_ = std::min(gain_ * config_.gain_step, config_.max_gain);
  else if (matched >= config_.good_matches && ratio > config_.good_ratio)
    gain_ = std::max(gain_ / config_.gain_step, config_.min_gain);
}

}  // namespace pllvo::nn
