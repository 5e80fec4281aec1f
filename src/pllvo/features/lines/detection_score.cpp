#include "pllvo/features/lines/detection_score.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace pllvo::lines {

namespace {
double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const auto mid = v.begin() + static_cast<long>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

// Length of the union of intervals clipped to [0, len].
double union_length(std::vector<std::pair<double, double>> iv, double len) {
  for (auto& [a, b] : iv) {
    a = std::clamp(a, 0.0, len);
    b = std::clamp(b, 0.0, len);
  }
  std::sort(iv.begin(), iv.end());
  double total = 0.0, cur_a = 0.0, cur_b = -1.0;
  for (const auto& [a, b] : iv) {
    if (a > cur_b) {
      if (cur_b > cur_a) total += cur_b - cur_a;
      cur_a = a;
      cur_b = b;
    } else {
      cur_b = std::max(cur_b, b);
    }
  }
  if (cur_b > cur_a) total += cur_b - cur_a;
  return total;
}
}  // namespace

double DetectionScore::mean_normal_error() const {
  if (normal_errors.empty()) return 0.0;
  double s = 0.0;
  for (double e : normal_errors) s += e;
  return s / static_cast<double>(normal_errors.size());
}

double DetectionScore::median_endpoint_error() const { return median(endpoint_errors); }

void DetectionScore::add(const DetectionScore& o) {
  detections += o.detections;
  correct += o.correct;
  truth_length += o.truth_length;
  covered_length += o.covered_length;
  normal_errors.insert(normal_errors.end(), o.normal_errors.begin(), o.normal_errors.end());
  endpoint_errors.insert(endpoint_errors.end(), o.endpoint_errors.begin(), o.endpoint_errors.end());
}

DetectionScore score_line_detections(const std::vector<LineSegment>& detected, const std::vector<LineSegment>& truth,
                                     const DetectionScoreConfig& config) {
  DetectionScore score;
  score.detections = static_cast<long>(detected.size());
  std::vector<std::vector<std::pair<double, double>>> covered(truth.size());
  const double tol = config.tolerance_px;
  for (const auto& d : detected) {
    int best = -1;
    double best_cost = std::numeric_limits<double>::max();
    for (size_t t = 0; t < truth.size(); ++t) {
      const double ds = point_segment_distance(d.start, truth[t]), de = point_segment_distance(d.end, truth[t]);
      if (ds <= tol && de <= tol && ds + de < best_cost) {
        best_cost = ds + de;
        best = static_cast<int>(t);
      }
    }
    if (best < 0) continue;
    ++score.correct;
    const LineSegment& t = truth[best];
    const double a = project_along(d.start, t), b = project_along(d.end, t);
    covered[best].emplace_back(std::min(a, b), std::max(a, b));
    score.normal_errors.push_back(std::abs(signed_line_distance(d.start, t)));
    score.normal_errors.push_back(std::abs(signed_line_distance(d.end, t)));
    // Whole edge in one piece: endpoints pair up with the true endpoints (either order).
    const double same = std::max((d.start - t.start).norm(), (d.end - t.end).norm());
    const double swapped = std::max((d.start - t.end).norm(), (d.end - t.start).norm());
    if (same <= tol) {
      score.endpoint_errors.push_back((d.start - t.start).norm());
      score.endpoint_errors.push_back((d.end - t.end).norm());
    } else if (swapped <= tol) {
      score.endpoint_errors.push_back((d.start - t.end).norm());
      score.endpoint_errors.push_back((d.end - t.start).norm());
    }
  }
  for (size_t t = 0; t < truth.size(); ++t) {
    const double len = truth[t].length();
    if (len < config.min_truth_length_px) continue;
    score.truth_length += len;
    score.covered_length += union_length(covered[t], len);
  }
  return score;
}

}  // namespace pllvo::lines
