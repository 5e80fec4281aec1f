#pragma once
// Merging of collinear line pieces. EDLines splits a straight edge where its chain breaks
// (noise, a crossing edge, a short occlusion); the VO wants one long line per physical edge.
#include <vector>

#include <Eigen/Core>

#include "pllvo/features/lines/line_segment.h"

namespace pllvo::lines {

struct CollinearMergeConfig {
  double max_angle_rad = 2.0 * M_PI / 180.0;  ///< directions differ by at most this
  double max_distance_px = 1.5;               ///< endpoints of each piece lie this close to the other's line
  double max_gap_px = 8.0;                    ///< gap along the line (overlapping pieces have gap 0)
};

/// A segment with the points that support it (edge pixels); the merge refits on their union.
/// A segment without support points is represented by its two endpoints.
struct SupportedSegment {
  LineSegment segment;
  std::vector<Eigen::Vector2d> support;
};

/// True when a and b pass the three merge tests.
bool can_merge(const LineSegment& a, const LineSegment& b, const CollinearMergeConfig& config);

/// Merges mergeable pairs greedily (longest first) until none is left, refitting each merged
/// segment by total least squares on the union of the supports; a merge whose refit leaves a
/// support point farther than max_distance_px from the new line is refused. Returns the number
/// of merges; `segments` keeps the survivors (the longer piece's id and max response).
int merge_collinear_segments(std::vector<SupportedSegment>& segments, const CollinearMergeConfig& config);

}  // namespace pllvo::lines
