#pragma once
// Scoring of detected line segments against ground-truth segments (synthetic frames).
//  - A detection is correct when it lies on true segments along its whole length: its two
//    endpoints, and points every `sample_spacing_px` between them, are each within
//    `tolerance_px` of a true segment whose direction is within `max_angle_deg` of the
//    detection's. For a single true segment this is the classic "both endpoints within 2 px of
//    a true segment" (the segment is convex); it also accepts one straight detection along a
//    chain of collinear true segments (a straight 3-D edge cut into pieces by lens distortion,
//    or two collinear 3-D edges meeting end to end, e.g. a door frame built from two quads),
//    and it rejects a detection that runs past the end of the truth or bridges a gap.
//  - Precision = correct / detections. Every true segment counts for precision, visible or not.
//  - Recall = share of the true length covered by correct detections (each piece's covered
//    length is the union of the projections on it of the correct detections lying on it),
//    counted over *visible* pieces only: pieces of 3-D edges (same id) at least
//    `min_truth_length_px` long in total in the frame, whose contrast (when the frame gives
//    contrasts) is at least `min_truth_contrast`.
//  - Normal error: perpendicular distance of the endpoints of correct detections to the line
//    of the true segment nearest to each (sub-pixel accuracy of the fitted line).
//  - Endpoint error: for correct detections whose two endpoints lie on the same 3-D edge and
//    are each within tolerance of that edge's two extreme endpoints in the frame (the whole
//    visible edge found in one piece), the distances between them.
#include <vector>

#include <opencv2/core.hpp>

#include "pllvo/features/lines/line_segment.h"

namespace pllvo::lines {

/// One frame with ground truth (a rendered or synthetic frame).
struct TruthFrame {
  cv::Mat image;                   ///< CV_8UC1
  std::vector<LineSegment> truth;  ///< true segments (visible parts), ids stable over a sequence
  /// Brightness difference across each true segment in the noise-free image (DN), one per
  /// segment; empty when unknown (every segment then counts as visible).
  std::vector<float> contrast;
};

struct DetectionScoreConfig {
  double tolerance_px = 2.0;
  double sample_spacing_px = 5.0;     ///< interior points checked along a detection
  double max_angle_deg = 10.0;        ///< a detection lies on true segments running this parallel
  double min_truth_length_px = 0.0;   ///< edges shorter than this (in the frame) are not asked for
  double min_truth_contrast = 0.0;    ///< pieces with less contrast (DN) are not asked for
};

struct DetectionScore {
  long detections = 0;
  long correct = 0;
  long frames = 0;
  double truth_length = 0.0;
  double covered_length = 0.0;
  std::vector<double> normal_errors;    ///< two per correct detection
  std::vector<double> endpoint_errors;  ///< two per complete detection

  double precision() const { return detections ? static_cast<double>(correct) / detections : 0.0; }
  double recall() const { return truth_length > 0 ? covered_length / truth_length : 0.0; }
  double lines_per_frame() const { return frames ? static_cast<double>(detections) / frames : 0.0; }
  double mean_normal_error() const;
  double median_endpoint_error() const;
  /// Accumulates another frame's score.
  void add(const DetectionScore& other);
};

DetectionScore score_line_detections(const std::vector<LineSegment>& detected, const std::vector<LineSegment>& truth,
                                     const DetectionScoreConfig& config = {});
DetectionScore score_line_detections(const std::vector<LineSegment>& detected, const TruthFrame& frame,
                                     const DetectionScoreConfig& config = {});

/// Where a detection lies on the truth (the criterion for a correct detection above).
struct TruthMatch {
  bool correct = false;
  int start_piece = -1, end_piece = -1;  ///< index of the true segment nearest to each endpoint
};
TruthMatch match_detection(const LineSegment& s, const std::vector<LineSegment>& truth,
                           const DetectionScoreConfig& config = {});

}  // namespace pllvo::lines
