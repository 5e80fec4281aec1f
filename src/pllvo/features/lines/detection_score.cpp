#include "pllvo/features/lines/detection_score.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <map>
#include <utility>

#include "pllvo/common/statistics.h"

namespace pllvo::lines {

namespace {

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

// The pieces of each true edge (same id; a negative id is an edge of its own).
std::vector<std::vector<size_t>> group_by_edge(const std::vector<LineSegment>& truth) {
  std::vector<std::vector<size_t>> groups;
  std::map<int, size_t> index;
  for (size_t i = 0; i < truth.size(); ++i) {
    if (truth[i].id < 0) {
      groups.push_back({i});
      continue;
    }
    const auto [it, added] = index.emplace(truth[i].id, groups.size());
    if (added) groups.emplace_back();
    groups[it->second].push_back(i);
  }
  return groups;
}

// Candidate true segments for a detection: near it and about parallel.
std::vector<size_t> candidates(const LineSegment& d, const std::vector<LineSegment>& truth,
                               const DetectionScoreConfig& config) {
  std::vector<size_t> out;
  const double max_angle = config.max_angle_deg * M_PI / 180.0;
  for (size_t i = 0; i < truth.size(); ++i)
    if (acute_angle(d, truth[i]) <= max_angle && segment_distance(d, truth[i]) <= config.tolerance_px)
      out.push_back(i);
  return out;
}

// Nearest of the candidates to p within tolerance, or -1.
int nearest(const Eigen::Vector2d& p, const std::vector<LineSegment>& truth, const std::vector<size_t>& cands,
            double tol) {
  int best = -1;
  double d = tol;
  for (size_t i : cands)
    if (const double di = point_segment_distance(p, truth[i]); di <= d) d = di, best = static_cast<int>(i);
  return best;
}

// The two piece endpoints of an edge farthest apart: the ends of its visible extent.
std::pair<Eigen::Vector2d, Eigen::Vector2d> edge_extremes(const std::vector<LineSegment>& truth,
                                                          const std::vector<size_t>& edge) {
  std::vector<Eigen::Vector2d> pts;
  for (size_t i : edge) pts.push_back(truth[i].start), pts.push_back(truth[i].end);
  std::pair<Eigen::Vector2d, Eigen::Vector2d> best{pts[0], pts[1]};
  double d = -1;
  for (size_t i = 0; i < pts.size(); ++i)
    for (size_t j = i + 1; j < pts.size(); ++j)
      if (const double dij = (pts[i] - pts[j]).norm(); dij > d) d = dij, best = {pts[i], pts[j]};
  return best;
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
  frames += o.frames;
  truth_length += o.truth_length;
  covered_length += o.covered_length;
  normal_errors.insert(normal_errors.end(), o.normal_errors.begin(), o.normal_errors.end());
  endpoint_errors.insert(endpoint_errors.end(), o.endpoint_errors.begin(), o.endpoint_errors.end());
}

TruthMatch match_detection(const LineSegment& d, const std::vector<LineSegment>& truth,
                           const DetectionScoreConfig& config) {
  TruthMatch m;
  const auto cands = candidates(d, truth, config);
  if (cands.empty()) return m;
  const double tol = config.tolerance_px;
  m.start_piece = nearest(d.start, truth, cands, tol);
  m.end_piece = nearest(d.end, truth, cands, tol);
  if (m.start_piece < 0 || m.end_piece < 0) return m;
  const int n = config.sample_spacing_px > 0 ? static_cast<int>(d.length() / config.sample_spacing_px) : 0;
  for (int k = 1; k < n; ++k)
    if (nearest(d.at(static_cast<double>(k) / n), truth, cands, tol) < 0) return m;
  m.correct = true;
  return m;
}

DetectionScore score_line_detections(const std::vector<LineSegment>& detected, const std::vector<LineSegment>& truth,
                                     const DetectionScoreConfig& config) {
  TruthFrame frame;
  frame.truth = truth;
  return score_line_detections(detected, frame, config);
}

DetectionScore score_line_detections(const std::vector<LineSegment>& detected, const TruthFrame& frame,
                                     const DetectionScoreConfig& config) {
  const auto& truth = frame.truth;
  DetectionScore score;
  score.frames = 1;
  score.detections = static_cast<long>(detected.size());
  const auto groups = group_by_edge(truth);
  std::vector<std::vector<std::pair<double, double>>> covered(truth.size());
  const double tol = config.tolerance_px;
  std::map<int, size_t> group_of;  // truth id -> index in groups
  for (size_t g = 0; g < groups.size(); ++g)
    if (truth[groups[g].front()].id >= 0) group_of[truth[groups[g].front()].id] = g;
  for (const auto& d : detected) {
    const TruthMatch m = match_detection(d, truth, config);
    if (!m.correct) continue;
    ++score.correct;
    // Coverage: the pieces the detection lies on (near it and parallel, touched by a sample).
    for (size_t i : candidates(d, truth, config)) {
      bool touched = false;
      const int n = std::max(1, static_cast<int>(d.length() / std::max(config.sample_spacing_px, 1.0)));
      for (int k = 0; k <= n && !touched; ++k)
        touched = point_segment_distance(d.at(static_cast<double>(k) / n), truth[i]) <= tol;
      if (!touched) continue;
      const double a = project_along(d.start, truth[i]), b = project_along(d.end, truth[i]);
      covered[i].emplace_back(std::min(a, b), std::max(a, b));
    }
    score.normal_errors.push_back(std::abs(signed_line_distance(d.start, truth[m.start_piece])));
    score.normal_errors.push_back(std::abs(signed_line_distance(d.end, truth[m.end_piece])));
    // Whole edge in one piece: endpoints on one 3-D edge pair up with its ends (either order).
    const int id = truth[m.start_piece].id;
    if (id < 0 || id != truth[m.end_piece].id) continue;
    const auto [ta, tb] = edge_extremes(truth, groups[group_of.at(id)]);
    const double same = std::max((d.start - ta).norm(), (d.end - tb).norm());
    const double swapped = std::max((d.start - tb).norm(), (d.end - ta).norm());
    if (same <= tol) {
      score.endpoint_errors.push_back((d.start - ta).norm());
      score.endpoint_errors.push_back((d.end - tb).norm());
    } else if (swapped <= tol) {
      score.endpoint_errors.push_back((d.start - tb).norm());
      score.endpoint_errors.push_back((d.end - ta).norm());
    }
  }
  const bool has_contrast = frame.contrast.size() == truth.size();
  for (const auto& edge : groups) {
    double edge_length = 0.0;
    for (size_t i : edge) edge_length += truth[i].length();
    if (edge_length < config.min_truth_length_px) continue;
    for (size_t i : edge) {
      if (has_contrast && frame.contrast[i] < config.min_truth_contrast) continue;
      const double len = truth[i].length();
      score.truth_length += len;
      score.covered_length += union_length(covered[i], len);
    }
  }
  return score;
}

}  // namespace pllvo::lines
