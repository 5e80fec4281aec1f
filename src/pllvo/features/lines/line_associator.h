#pragma once
// Line association between two keyframes (PLL-VO keyframe matching): lines are associated
// through the matched points near them, with LBD descriptors (OpenCV line_descriptor) as a
// second cue and a geometric check.
//
//  1. Point cue. A point match (pa, pb) VOTES for every pair (line a, line b) with pa within
//     `point_distance_px` of segment a and pb within it of segment b. A line a is associated
//     with the line b that collects the most votes when there are at least `min_votes`, clearly
//     more than the runner-up (`vote_ratio`), and a is also b's best.
//  2. Descriptor cue. Lines left unassociated are matched by LBD Hamming distance: mutual
//     nearest neighbours below `max_descriptor_distance` passing the ratio test.
//  3. Geometric check. With at least `min_matches_for_homography` point matches, a homography H
//     is fitted to them (RANSAC) and every association must agree with it: line a mapped by H
//     lies within `max_angle_deg` of line b's direction, its midpoint within `max_distance_px`
//     of line b's infinite line, and the two overlap along the line. H is exact for a plane or a
//     rotating camera and approximate otherwise, hence the loose defaults; without it the point
//     cue is trusted as is and the descriptor cue is not used (nothing would check it).
#include <vector>

#include <opencv2/core.hpp>

#include "pllvo/common/yaml_config.h"
#include "pllvo/features/lines/line_segment.h"

namespace pllvo::lines {

struct PointMatch {
  Eigen::Vector2d a;  ///< pixel in frame A
  Eigen::Vector2d b;  ///< matched pixel in frame B
};

struct LineAssociatorConfig {
  double point_distance_px = 3.0;
  int min_votes = 2;
  double vote_ratio = 1.5;
  bool use_descriptors = true;
  int max_descriptor_distance = 60;  ///< of 256 bits
  double descriptor_ratio = 0.8;
  int min_matches_for_homography = 8;
  double homography_ransac_px = 5.0;
  double max_angle_deg = 10.0;
  double max_distance_px = 15.0;

  void load(const ConfigNode& node);
};

enum class AssociationCue { Points, Descriptor };

struct LineMatch {
  int a = -1;  ///< index into frame A's lines
  int b = -1;  ///< index into frame B's lines
  AssociationCue cue = AssociationCue::Points;
  int votes = 0;                 ///< supporting point matches (point cue)
  int descriptor_distance = -1;  ///< Hamming distance when descriptors were given, else -1
};

/// LBD descriptors (256 bits: one CV_8U row of 32 bytes per line, in order). Each line is
/// described with its brighter side on a fixed side, so the descriptor does not depend on
/// which endpoint is called start. Empty Mat for no lines.
cv::Mat compute_lbd_descriptors(const cv::Mat& gray, const std::vector<LineSegment>& lines);

class LineAssociator {
 public:
  explicit LineAssociator(LineAssociatorConfig config = {});

  /// One-to-one associations. Descriptors are optional (empty Mat: point cue only); when given,
  /// their row counts must match the line counts.
  std::vector<LineMatch> associate(const std::vector<LineSegment>& lines_a, const std::vector<LineSegment>& lines_b,
                                   const std::vector<PointMatch>& point_matches, const cv::Mat& descriptors_a = {},
                                   const cv::Mat& descriptors_b = {}) const;

  const LineAssociatorConfig& config() const { return config_; }

 private:
  LineAssociatorConfig config_;
};

}  // namespace pllvo::lines
