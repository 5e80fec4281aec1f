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
#include "pllvo/features/lines/synth_line_sequence.h"

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
};

/// Detects lines in frame 0, applies the cross constraint, and tracks them frame to frame to
/// the end without re-detection; only lines that start on a true segment are followed.
/// `motions` (optional, frame-0 pixel -> frame-k pixel) enables endpoint errors.
TrackingEvaluation evaluate_tracking(const std::vector<TruthFrame>& frames, const LineDetectorConfig& detector,
                                     const CrossConstraintConfig& cross, const LineTrackerConfig& tracker,
                                     const std::vector<Eigen::Isometry2d>* motions = nullptr,
                                     double tolerance_px = 2.0);

/// Tracking on a synthetic sequence against the projected truth. Lines are detected (cross
/// constraint applied) at frames 0, L, 2L, ... and each set is tracked frame to frame for L
/// steps (L = `chain_length`, like re-detection at keyframes); only lines that start on a true
/// edge (the detection criterion of detection_score.h) are followed. Each endpoint is tied to
/// the point of its 3-D edge seen there at the start, and that point's projection is where the
/// tracked endpoint should be later.
struct SynthTrackingEvaluation {
  int chain_length = 0;
  long detected = 0;  ///< lines detected at the chain starts (after the cross constraint)
  long started = 0;   ///< of which on a true edge: the lines followed
  /// Index j = after j steps (index 0 = started): lines still tracked, and lines lost because
  /// they left the image (the tracker's out-of-image status), cumulative.
  std::vector<long> tracked, left_image;
  /// Index j: |tracked endpoint - projected truth| after j steps (px), for lines never clipped
  /// at the border whose true endpoint is in front of the camera and inside the image. Index 0:
  /// the detected endpoints themselves (their distance to the true edge: the starting error).
  std::vector<std::vector<double>> endpoint_errors;
  /// Distance of tracked endpoints to the true edge (nearest piece with the same id) in the
  /// frame, all steps: drift off the edge.
  std::vector<double> normal_errors;

  /// Share of the lines tracked at step j-1 that are still tracked at step j.
  double kept_share(int j) const;
  /// Lines kept per step, pooled over the steps: sum of tracked[1..L] / sum of tracked[0..L-1].
  double kept_share_per_frame() const;
  /// Same, not counting lines lost because they left the image.
  double kept_share_per_frame_in_image() const;
  std::vector<double> all_endpoint_errors() const;  ///< steps 1..L
};

SynthTrackingEvaluation evaluate_synth_tracking(const SynthLineSequence& seq, const LineDetectorConfig& detector,
                                                const CrossConstraintConfig& cross, const LineTrackerConfig& tracker,
                                                int chain_length, const DetectionScoreConfig& score = {});

}  // namespace pllvo::lines
