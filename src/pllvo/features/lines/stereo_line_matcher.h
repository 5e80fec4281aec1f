#pragma once
// Left-right line matching in a rectified stereo pair, for metric 3-D lines on a keyframe
// (and a stereo start in scenes where lines, not points, carry the geometry).
//
// In a rectified pair a 3-D line projects to two segments with the same rows and a horizontal
// shift (the disparity) that varies linearly along them. A candidate pair therefore needs: a
// nearly equal orientation, enough shared rows, and a positive disparity within range at both
// ends of the shared rows. Lines closer to horizontal than `min_angle_from_horizontal_deg` are
// skipped: their rows do not pin a point along them, so the disparity is undetermined. Among
// the candidates of a left line, LBD descriptors (when given) pick the match: mutual best,
// below a Hamming distance, passing a ratio test; without descriptors only a left line with a
// single candidate (which has that left line as its single candidate too) is matched.
#include <vector>

#include <opencv2/core.hpp>

#include "pllvo/common/yaml_config.h"
#include "pllvo/features/lines/line_associator.h"
#include "pllvo/features/lines/line_segment.h"

namespace pllvo::lines {

struct StereoLineMatcherConfig {
  /// On every stereo keyframe. Off by default: measured neutral to worse on the synthetic suite
  /// (docs/vo.md); the VO turns it on for plain keyframes (VoConfig::plain_scene).
  bool enabled = false;
  double max_angle_deg = 3.0;                   ///< orientation difference (rectified: ~0)
  double min_angle_from_horizontal_deg = 15.0;  ///< flatter lines have no usable disparity
  double min_row_overlap = 0.6;                 ///< shared rows / rows of the shorter segment
  double min_disparity_px = 0.5;                ///< at both ends of the shared rows
  double max_disparity_px = 150.0;
  int max_descriptor_distance = 60;  ///< Hamming, of 256 bits
  double descriptor_ratio = 0.8;     ///< best / second-best candidate distance
  /// Triangulation: smallest angle between the left and right back-projected planes (about
  /// disparity / focal for a vertical line; below it the depth is too uncertain).
  double min_plane_angle_deg = 0.5;

  void load(const ConfigNode& node);
};

/// Stereo line matches: `a` indexes the left lines, `b` the right ones. Descriptors are
/// optional (empty: geometry only, unique candidates); when given, one row per line.
std::vector<LineMatch> match_stereo_lines(const std::vector<LineSegment>& left, const std::vector<LineSegment>& right,
                                          const cv::Mat& left_descriptors, const cv::Mat& right_descriptors,
                                          const StereoLineMatcherConfig& config);

/// Disparity (left x - right x) of the two segments at image row y (their infinite lines).
double disparity_at_row(const LineSegment& left, const LineSegment& right, double y);

}  // namespace pllvo::lines
