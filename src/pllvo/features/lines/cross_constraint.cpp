#include "pllvo/features/lines/cross_constraint.h"

#include <cmath>

#include "pllvo/features/lines/line_overlaps.h"

namespace pllvo::lines {

void CrossConstraintConfig::load(const ConfigNode& node) {
  node.get("enabled", enabled);
  node.get("overlap_distance_px", overlap_distance_px);
  node.get("max_overlap_angle_deg", max_overlap_angle_deg);
  node.get("max_shallow_overlaps", max_shallow_overlaps);
  node.reject_unknown_keys();
  if (overlap_distance_px < 0.0) throw InputError(node.file(), node.path("overlap_distance_px"), "must be >= 0");
  if (max_overlap_angle_deg < 0.0 || max_overlap_angle_deg > 90.0)
    throw InputError(node.file(), node.path("max_overlap_angle_deg"), "must be in [0, 90]");
  if (max_shallow_overlaps < 0) throw InputError(node.file(), node.path("max_shallow_overlaps"), "must be >= 0");
}

std::vector<LineSegment> apply_cross_constraint(const std::vector<LineSegment>& lines,
                                                const CrossConstraintConfig& config, std::vector<uint8_t>* removed) {
  std::vector<int> shallow(lines.size(), 0);
  if (config.enabled) {
    const double max_angle = config.max_overlap_angle_deg * M_PI / 180.0;
    for (const auto& o : find_overlaps(lines, config.overlap_distance_px)) {
      if (o.angle_rad >= max_angle) continue;
      ++shallow[o.a];
      ++shallow[o.b];
    }
  }
  std::vector<LineSegment> kept;
  kept.reserve(lines.size());
  if (removed) removed->assign(lines.size(), 0);
  for (size_t i = 0; i < lines.size(); ++i) {
    if (shallow[i] > config.max_shallow_overlaps) {
      if (removed) (*removed)[i] = 1;
      continue;
    }
    kept.push_back(lines[i]);
  }
  return kept;
}

}  // namespace pllvo::lines
