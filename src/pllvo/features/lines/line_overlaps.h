#pragma once
// Overlapping line pairs, shared by the cross constraint (eq. 7) and the overlap-angle set T
// (eq. 9).
//
// Definition: two segments OVERLAP when they intersect or come within `overlap_distance_px` of
// each other (smallest distance between any two of their points, so touching endpoints and
// T- or L-junctions count, while disjoint parallel segments farther apart do not). Their
// OVERLAP ANGLE is the acute angle between their directions, in [0, pi/2]: ~pi/2 for a regular
// crossing, ~0 for nearly parallel lines lying on top of or next to each other.
#include <vector>

#include "pllvo/features/lines/line_segment.h"

namespace pllvo::lines {

struct LineOverlap {
  int a = -1;  ///< indices into the line list, a < b
  int b = -1;
  double angle_rad = 0.0;
};

/// Every overlapping pair of `lines` (quadratic in the number of lines, with a bounding-box
/// test first, which is cheap for the few hundred lines of a frame).
std::vector<LineOverlap> find_overlaps(const std::vector<LineSegment>& lines, double overlap_distance_px);

}  // namespace pllvo::lines
