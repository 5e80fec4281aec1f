#include "pllvo/features/lines/stereo_line_matcher.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "pllvo/common/error.h"

namespace pllvo::lines {

void StereoLineMatcherConfig::load(const ConfigNode& node) {
  node.get("enabled", enabled);
  node.get("max_angle_deg", max_angle_deg);
  node.get("min_angle_from_horizontal_deg", min_angle_from_horizontal_deg);
  node.get("min_row_overlap", min_row_overlap);
  node.get("min_disparity_px", min_disparity_px);
  node.get("max_disparity_px", max_disparity_px);
  node.get("max_descriptor_distance", max_descriptor_distance);
  node.get("descriptor_ratio", descriptor_ratio);
  node.get("min_plane_angle_deg", min_plane_angle_deg);
  node.reject_unknown_keys();
  if (max_angle_deg <= 0) throw InputError(node.file(), node.path("max_angle_deg"), "must be > 0");
  if (min_angle_from_horizontal_deg <= 0 || min_angle_from_horizontal_deg > 90)
    throw InputError(node.file(), node.path("min_angle_from_horizontal_deg"), "must be in (0, 90]");
  if (min_row_overlap <= 0 || min_row_overlap > 1)
    throw InputError(node.file(), node.path("min_row_overlap"), "must be in (0, 1]");
  if (max_disparity_px <= min_disparity_px)
    throw InputError(node.file(), node.path("max_disparity_px"), "must be > min_disparity_px");
  if (descriptor_ratio <= 0 || descriptor_ratio > 1)
    throw InputError(node.file(), node.path("descriptor_ratio"), "must be in (0, 1]");
  if (min_plane_angle_deg <= 0) throw InputError(node.file(), node.path("min_plane_angle_deg"), "must be > 0");
}

double disparity_at_row(const LineSegment& left, const LineSegment& right, double y) {
  auto x_at = [](const LineSegment& s, double row) {
    const Eigen::Vector2d d = s.end - s.start;
    return s.start.x() + d.x() * (row - s.start.y()) / d.y();
  };
  return x_at(left, y) - x_at(right, y);
}

namespace {

double angle_from_horizontal(const LineSegment& s) {
  const Eigen::Vector2d d = s.end - s.start;
  return std::atan2(std::abs(d.y()), std::abs(d.x()));
}

bool geometric_candidate(const LineSegment& l, const LineSegment& r, const StereoLineMatcherConfig& c) {
  if (acute_angle(l, r) > c.max_angle_deg * M_PI / 180.0) return false;
  const double l0 = std::min(l.start.y(), l.end.y()), l1 = std::max(l.start.y(), l.end.y());
  const double r0 = std::min(r.start.y(), r.end.y()), r1 = std::max(r.start.y(), r.end.y());
  const double lo = std::max(l0, r0), hi = std::min(l1, r1);
  if (hi - lo < c.min_row_overlap * std::min(l1 - l0, r1 - r0)) return false;
  for (double y : {lo, hi}) {
    const double d = disparity_at_row(l, r, y);
    if (!(d >= c.min_disparity_px && d <= c.max_disparity_px)) return false;
  }
  return true;
}

}  // namespace

std::vector<LineMatch> match_stereo_lines(const std::vector<LineSegment>& left, const std::vector<LineSegment>& right,
                                          const cv::Mat& left_descriptors, const cv::Mat& right_descriptors,
                                          const StereoLineMatcherConfig& config) {
  const bool have_desc = !left_descriptors.empty() && !right_descriptors.empty();
  if (have_desc && (left_descriptors.rows != static_cast<int>(left.size()) ||
                    right_descriptors.rows != static_cast<int>(right.size())))
    throw InputError("stereo line matching: one descriptor row per line is required");
  const int nl = static_cast<int>(left.size()), nr = static_cast<int>(right.size());
  constexpr int kNone = std::numeric_limits<int>::max();
  // cost[i][j]: descriptor distance of a geometric candidate (0 without descriptors), else kNone.
  std::vector<std::vector<int>> cost(nl, std::vector<int>(nr, kNone));
  const double min_slope = config.min_angle_from_horizontal_deg * M_PI / 180.0;
  for (int i = 0; i < nl; ++i) {
    if (angle_from_horizontal(left[i]) < min_slope) continue;
    for (int j = 0; j < nr; ++j) {
      if (angle_from_horizontal(right[j]) < min_slope || !geometric_candidate(left[i], right[j], config)) continue;
      cost[i][j] = have_desc ? static_cast<int>(cv::norm(left_descriptors.row(i), right_descriptors.row(j),
                                                         cv::NORM_HAMMING))
                             : 0;
    }
  }
  // Best and second best per row and per column.
  auto best_two = [&](int n, auto at) {
    int best = -1, first = kNone, second = kNone;
    for (int k = 0; k < n; ++k) {
      const int c = at(k);
      if (c < first) {
        second = first;
        first = c;
        best = k;
      } else if (c < second) {
        second = c;
      }
    }
    return std::make_tuple(best, first, second);
  };
  std::vector<LineMatch> matches;
  for (int i = 0; i < nl; ++i) {
    const auto [j, first, second] = best_two(nr, [&](int k) { return cost[i][k]; });
    if (j < 0 || first == kNone) continue;
    const auto [back, col_first, col_second] = best_two(nl, [&](int k) { return cost[k][j]; });
    if (back != i) continue;
    if (have_desc) {
      if (first > config.max_descriptor_distance) continue;
      const double ratio = config.descriptor_ratio;
      if (second != kNone && first > ratio * second) continue;
      if (col_second != kNone && col_first > ratio * col_second) continue;
    } else if (second != kNone || col_second != kNone) {
      continue;  // ambiguous without a descriptor
    }
    LineMatch m;
    m.a = i;
    m.b = j;
    m.cue = AssociationCue::Descriptor;
    m.descriptor_distance = have_desc ? first : -1;
    matches.push_back(m);
  }
  return matches;
}

}  // namespace pllvo::lines
