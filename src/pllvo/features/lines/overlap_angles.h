#pragma once
// The overlap-angle set T of a keyframe (PLL-VO eq. 9): the overlap angles of every
// overlapping pair of its lines (line_overlaps.h). The structure of a view (how its edges
// meet) changes when the camera sees a new part of the scene, so the keyframe policy compares
// T of the current frame with T of the last keyframe and asks for a new keyframe when the
// distance between the two sets exceeds its threshold.
#include <vector>

#include "pllvo/common/yaml_config.h"
#include "pllvo/features/lines/line_segment.h"

namespace pllvo::lines {

struct OverlapAngleConfig {
  double overlap_distance_px = 2.0;  ///< as in the cross constraint
  int histogram_bins = 9;            ///< bins over [0, 90] degrees (for reports and plots)

  void load(const ConfigNode& node);
};

struct OverlapAngleSet {
  std::vector<double> angles_deg;  ///< sorted, each in [0, 90]
  std::vector<double> histogram;   ///< share of the angles per bin (sums to 1; all 0 when empty)

  size_t size() const { return angles_deg.size(); }
};

OverlapAngleSet overlap_angle_set(const std::vector<LineSegment>& lines, const OverlapAngleConfig& config = {});

/// Distance between two sets, in degrees: the 1-D earth mover's (Wasserstein-1) distance between
/// their empirical angle distributions, i.e. the mean absolute difference of their quantile
/// functions. 0 for identical distributions, at most 90; 0 when both are empty and 90 when only
/// one is (a view with no junctions at all is as different as it gets). Independent of binning
/// and of how many pairs each set has.
double overlap_angle_distance(const OverlapAngleSet& a, const OverlapAngleSet& b);

}  // namespace pllvo::lines
