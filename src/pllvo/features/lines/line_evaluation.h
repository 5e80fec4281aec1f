#pragma once
// Evaluation of the line front end on frames with ground-truth segments (the built-in polygon
// scenes now, the synthetic sequences of `pllvo synth` later): any source that provides an
// 8-bit image and its true segments per frame (ids stable over a sequence) can be scored.
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "pllvo/features/lines/cross_constraint.h"
#include "pllvo/features/lines/detection_score.h"
#include "pllvo/features/lines/line_detector.h"
#include "pllvo/features/lines/line_tracker.h"

namespace pllvo::lines {

/// Detection scores of the compared detectors on the same frames, in the same run.
struct DetectorComparison {
  DetectionScore ours;            ///< LineDetector as configured
  DetectionScore edlines;         ///< plain EdgeDrawing/EDLines, OpenCV defaults
  DetectionScore lsd;             ///< OpenCV LSD (cv::createLineSegmentDetector defaults)
  DetectionScore lsd_min_length;  ///< LSD keeping segments >= our min_length_px (same length filter)
};

/// `frames` is the number of frames scored. Pass min_truth_length_px in `score` to ignore true
/// segments that no detector is asked to find (shorter than the minimum length).
DetectorComparison compare_detectors(const std::vector<TruthFrame>& frames, const LineDetectorConfig& detector,
                                     const DetectionScoreConfig& score = {});

/// OpenCV's LSD with its defaults, as segments.
std::vector<LineSegment> detect_lsd(const cv::Mat& gray);

struct TrackingEvaluation {
  int detected = 0;  ///< lines detected (after the cross constraint) in the first frame
  int on_truth = 0;  ///< of which correct (both endpoints within tolerance of a true segment)
  std::vector<int> kept_per_frame;  ///< correct lines still tracked at each frame (frame 0 = on_truth)
  /// Distance of each tracked endpoint to the true segment it started on (same truth id),
  /// over all frames after the first: measures drift off the edge.
  std::vector<double> normal_errors;
  /// With known motions (polygon sequences): distance of each tracked endpoint to where the
  /// motion puts the detected endpoint (lines not clipped at the border).
  std::vector<double> endpoint_errors;

  double kept_share() const;  ///< kept at the last frame / on_truth
  static double median(std::vector<double> v);
};

/// Detects lines in frame 0, applies the cross constraint, and tracks them frame to frame to
/// the end without re-detection; only lines that start on a true segment are followed.
/// `motions` (optional, frame-0 pixel -> frame-k pixel) enables endpoint errors.
TrackingEvaluation evaluate_tracking(const std::vector<TruthFrame>& frames, const LineDetectorConfig& detector,
                                     const CrossConstraintConfig& cross, const LineTrackerConfig& tracker,
                                     const std::vector<Eigen::Isometry2d>* motions = nullptr,
                                     double tolerance_px = 2.0);

}  // namespace pllvo::lines
