#include "pllvo/features/lines/collinear_merge.h"

#include <algorithm>
#include <cmath>

#include "pllvo/features/lines/line_fit.h"

namespace pllvo::lines {

bool can_merge(const LineSegment& a, const LineSegment& b, const CollinearMergeConfig& config) {
  const Eigen::Vector2d da = a.direction(), db = b.direction();
  if (std::abs(da.dot(db)) < std::cos(config.max_angle_rad)) return false;
  const Eigen::Vector2d na(-da.y(), da.x()), nb(-db.y(), db.x());
  const double m = config.max_distance_px;
  if (std::abs(na.dot(b.start - a.start)) > m || std::abs(na.dot(b.end - a.start)) > m ||
      std::abs(nb.dot(a.start - b.start)) > m || std::abs(nb.dot(a.end - b.start)) > m)
    return false;
  // Gap between the two intervals along a's direction.
  const double t0 = da.dot(b.start - a.start), t1 = da.dot(b.end - a.start);
  const double lo = std::min(t0, t1), hi = std::max(t0, t1);
  const double gap = std::max({0.0, lo - a.length(), -hi});
  return gap <= config.max_gap_px;
}

namespace {
void ensure_support(SupportedSegment& s) {
  if (s.support.empty()) s.support = {s.segment.start, s.segment.end};
}

// Refit on the union; false (and no change) when a support point strays from the new line.
bool try_merge(SupportedSegment& into, const SupportedSegment& other, double max_distance) {
  std::vector<Eigen::Vector2d> pts = into.support;
  pts.insert(pts.end(), other.support.begin(), other.support.end());
  const LineFit fit = fit_line_tls(pts);
  const Eigen::Vector2d n(-fit.direction.y(), fit.direction.x());
  for (const auto& p : pts)
    if (std::abs(n.dot(p - fit.centroid)) > max_distance) return false;
  LineSegment merged = segment_from_fit(fit, pts, into.segment);
  merged.response = std::max(into.segment.response, other.segment.response);
  into.segment = merged;
  into.support = std::move(pts);
  return true;
}
}  // namespace

int merge_collinear_segments(std::vector<SupportedSegment>& segments, const CollinearMergeConfig& config) {
  for (auto& s : segments) ensure_support(s);
  std::sort(segments.begin(), segments.end(), [](const SupportedSegment& a, const SupportedSegment& b) {
    return a.segment.length() > b.segment.length();
  });
  // Candidates come from an orientation-sorted index, so each piece is only compared with the
  // few pieces of nearly the same orientation (orientation wraps at pi).
  std::vector<std::pair<double, int>> by_angle(segments.size());
  for (size_t i = 0; i < segments.size(); ++i) by_angle[i] = {segments[i].segment.orientation(), static_cast<int>(i)};
  std::sort(by_angle.begin(), by_angle.end());
  auto for_each_near = [&](double theta, double window, auto&& fn) {
    auto visit = [&](double a, double b) {
      auto it = std::lower_bound(by_angle.begin(), by_angle.end(), std::make_pair(a, -1));
      for (; it != by_angle.end() && it->first <= b; ++it) fn(it->second);
    };
    visit(std::max(0.0, theta - window), std::min(M_PI, theta + window));
    if (theta - window < 0.0) visit(theta - window + M_PI, M_PI);
    if (theta + window > M_PI) visit(0.0, theta + window - M_PI);
  };
  // Merged segments change orientation slightly; the window keeps a margin for that.
  const double window = 2.0 * config.max_angle_rad;

  std::vector<bool> alive(segments.size(), true);
  int merges = 0;
  for (size_t i = 0; i < segments.size(); ++i) {
    if (!alive[i]) continue;
    // After a merge segment i has grown, so pieces rejected before may now fit: rescan.
    bool grew = true;
    while (grew) {
      grew = false;
      std::vector<int> candidates;
      const LineSegment& si = segments[i].segment;
      const double reach = config.max_gap_px + config.max_distance_px;
      const double xmin = std::min(si.start.x(), si.end.x()) - reach, xmax = std::max(si.start.x(), si.end.x()) + reach;
      const double ymin = std::min(si.start.y(), si.end.y()) - reach, ymax = std::max(si.start.y(), si.end.y()) + reach;
      for_each_near(si.orientation(), window, [&](int j) {
        if (j <= static_cast<int>(i) || !alive[j]) return;
        // Cheap rejection: j must come within reach of i's bounding box.
        const LineSegment& sj = segments[j].segment;
        if (std::max(sj.start.x(), sj.end.x()) < xmin || std::min(sj.start.x(), sj.end.x()) > xmax ||
            std::max(sj.start.y(), sj.end.y()) < ymin || std::min(sj.start.y(), sj.end.y()) > ymax)
          return;
        candidates.push_back(j);
      });
      std::sort(candidates.begin(), candidates.end());
      for (int j : candidates) {
        if (!can_merge(segments[i].segment, segments[j].segment, config)) continue;
        if (!try_merge(segments[i], segments[j], config.max_distance_px)) continue;
        alive[j] = false;
        ++merges;
        grew = true;
      }
    }
  }
  std::vector<SupportedSegment> kept;
  kept.reserve(segments.size());
  for (size_t i = 0; i < segments.size(); ++i)
    if (alive[i]) kept.push_back(std::move(segments[i]));
  segments = std::move(kept);
  return merges;
}

}  // namespace pllvo::lines
