#pragma once
// Scoring of detected line segments against ground-truth segments (synthetic frames).
//  - A detection is correct when both its endpoints lie within `tolerance_px` of the same true
//    segment (point-to-segment distance): it lies on a real edge and does not run past it.
//  - Precision = correct / detections.
//  - Recall = share of the total true length covered by correct detections (each true segment's
//    covered length is the union of its correct detections' projections on it), counted over
//    true segments at least `min_truth_length_px` long.
//  - Normal error: perpendicular distance of the endpoints of correct detections to their true
//    line (sub-pixel accuracy of the fitted line).
//  - Endpoint error: for correct detections whose two endpoints are each within tolerance of the
//    two true endpoints (the whole edge found in one piece), the distances between them.
#include <vector>

#include <opencv2/core.hpp>

#include "pllvo/features/lines/line_segment.h"

namespace pllvo::lines {

/// One frame with ground truth (a rendered or synthetic frame).
struct TruthFrame {
  cv::Mat image;                   ///< CV_8UC1
  std::vector<LineSegment> truth;  ///< true segments (visible parts), ids stable over a sequence
};

struct DetectionScoreConfig {
  double tolerance_px = 2.0;
  double min_truth_length_px = 0.0;
};

struct DetectionScore {
  long detections = 0;
  long correct = 0;
  double truth_length = 0.0;
  double covered_length = 0.0;
  std::vector<double> normal_errors;    ///< two per correct detection
  std::vector<double> endpoint_errors;  ///< two per complete detection

  double precision() const { return detections ? static_cast<double>(correct) / detections : 0.0; }
  double recall() const { return truth_length > 0 ? covered_length / truth_length : 0.0; }
  double mean_normal_error() const;
  double median_endpoint_error() const;
  /// Accumulates another frame's score.
  void add(const DetectionScore& other);
};

DetectionScore score_line_detections(const std::vector<LineSegment>& detected, const std::vector<LineSegment>& truth,
                                     const DetectionScoreConfig& config = {});

}  // namespace pllvo::lines
