#include "pllvo/features/lines/overlap_angles.h"

#include <algorithm>
#include <cmath>

#include "pllvo/features/lines/line_overlaps.h"

namespace pllvo::lines {

void OverlapAngleConfig::load(const ConfigNode& node) {
  node.get("overlap_distance_px", overlap_distance_px);
  node.get("histogram_bins", histogram_bins);
  node.reject_unknown_keys();
  if (histogram_bins < 1) throw InputError(node.file(), node.path("histogram_bins"), "must be >= 1");
}

OverlapAngleSet overlap_angle_set(const std::vector<LineSegment>& lines, const OverlapAngleConfig& config) {
  OverlapAngleSet set;
  for (const auto& o : find_overlaps(lines, config.overlap_distance_px))
    set.angles_deg.push_back(std::clamp(o.angle_rad * 180.0 / M_PI, 0.0, 90.0));
  std::sort(set.angles_deg.begin(), set.angles_deg.end());
  set.histogram.assign(std::max(1, config.histogram_bins), 0.0);
  const int bins = static_cast<int>(set.histogram.size());
  for (double a : set.angles_deg) set.histogram[std::min(bins - 1, static_cast<int>(a / 90.0 * bins))] += 1.0;
  if (!set.angles_deg.empty())
    for (double& h : set.histogram) h /= static_cast<double>(set.angles_deg.size());
  return set;
}

double overlap_angle_distance(const OverlapAngleSet& a, const OverlapAngleSet& b) {
  if (a.angles_deg.empty() && b.angles_deg.empty()) return 0.0;
  if (a.angles_deg.empty() || b.angles_deg.empty()) return 90.0;
  // Integrate |Qa(q) - Qb(q)| over q in [0, 1]; both quantile functions are step functions with
  // breaks at i/na and j/nb, so walk the merged breakpoints.
  const auto& x = a.angles_deg;
  const auto& y = b.angles_deg;
  const double na = static_cast<double>(x.size()), nb = static_cast<double>(y.size());
  size_t i = 0, j = 0;
  double q = 0.0, total = 0.0;
  while (i < x.size() && j < y.size()) {
    const double qa = (i + 1) / na, qb = (j + 1) / nb;
    const double next = std::min(qa, qb);
    total += (next - q) * std::abs(x[i] - y[j]);
    q = next;
    if (qa <= next) ++i;
    if (qb <= next) ++j;
  }
  return total;
}

}  // namespace pllvo::lines
