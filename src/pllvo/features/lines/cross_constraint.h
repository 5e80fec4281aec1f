#pragma once
// Cross constraint (PLL-VO eq. 7): a line that overlaps (line_overlaps.h) MORE than
// `max_shallow_overlaps` other lines at an overlap angle BELOW `max_overlap_angle_deg` is
// removed. Such bundles of nearly parallel, touching segments come from texture, noise or
// blurred double edges and give ambiguous, unstable lines; a regular crossing (large angle),
// a corner or a single parallel neighbour (the two sides of a thin bar) does not count against
// a line. Counts are taken on the input set, so the result does not depend on the line order.
#include <cstdint>
#include <vector>

#include "pllvo/common/yaml_config.h"
#include "pllvo/features/lines/line_segment.h"

namespace pllvo::lines {

struct CrossConstraintConfig {
  bool enabled = true;
  double overlap_distance_px = 2.0;
  double max_overlap_angle_deg = 15.0;
  int max_shallow_overlaps = 2;

  void load(const ConfigNode& node);
};

/// The lines that pass; `removed` (optional) gets one flag per input line.
std::vector<LineSegment> apply_cross_constraint(const std::vector<LineSegment>& lines,
                                                const CrossConstraintConfig& config,
                                                std::vector<uint8_t>* removed = nullptr);

}  // namespace pllvo::lines
