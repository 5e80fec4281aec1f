#include "pllvo/features/lines/line_evaluation.h"

#include <algorithm>
#include <limits>

#include <opencv2/imgproc.hpp>

namespace pllvo::lines {

std::vector<LineSegment> detect_lsd(const cv::Mat& gray) {
  std::vector<cv::Vec4f> raw;
  cv::createLineSegmentDetector()->detect(gray, raw);
  std::vector<LineSegment> out;
  out.reserve(raw.size());
  for (const auto& r : raw)
    out.emplace_back(Eigen::Vector2d(r[0], r[1]), Eigen::Vector2d(r[2], r[3]), static_cast<int>(out.size()));
  return out;
}

DetectorComparison compare_detectors(const std::vector<TruthFrame>& frames, const LineDetectorConfig& detector,
                                     const DetectionScoreConfig& score) {
  DetectorComparison c;
  LineDetector ours(detector);
  for (const auto& f : frames) {
    c.ours.add(score_line_detections(ours.detect(f.image), f.truth, score));
    c.edlines.add(score_line_detections(detect_edlines_plain(f.image, EdgeDrawingConfig::opencv_defaults()), f.truth,
                                        score));
    const auto lsd = detect_lsd(f.image);
    c.lsd.add(score_line_detections(lsd, f.truth, score));
    std::vector<LineSegment> long_lsd;
    for (const auto& s : lsd)
      if (s.length() >= detector.min_length_px) long_lsd.push_back(s);
    c.lsd_min_length.add(score_line_detections(long_lsd, f.truth, score));
  }
  return c;
}

double TrackingEvaluation::kept_share() const {
  return on_truth > 0 && !kept_per_frame.empty() ? static_cast<double>(kept_per_frame.back()) / on_truth : 0.0;
}

double TrackingEvaluation::median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const auto mid = v.begin() + static_cast<long>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

namespace {
// Truth id of the true segment both endpoints of `s` lie near, or -1.
int truth_id_of(const LineSegment& s, const std::vector<LineSegment>& truth, double tol) {
  int best = -1;
  double best_cost = std::numeric_limits<double>::max();
  for (const auto& t : truth) {
    const double a = point_segment_distance(s.start, t), b = point_segment_distance(s.end, t);
    if (a <= tol && b <= tol && a + b < best_cost) best_cost = a + b, best = t.id;
  }
  return best;
}

const LineSegment* find_truth(const std::vector<LineSegment>& truth, int id) {
  for (const auto& t : truth)
    if (t.id == id) return &t;
  return nullptr;
}
}  // namespace

TrackingEvaluation evaluate_tracking(const std::vector<TruthFrame>& frames, const LineDetectorConfig& detector,
                                     const CrossConstraintConfig& cross, const LineTrackerConfig& tracker_config,
                                     const std::vector<Eigen::Isometry2d>* motions, double tolerance_px) {
  TrackingEvaluation ev;
  if (frames.empty()) return ev;
  LineDetector det(detector);
  const LineTracker tracker(tracker_config);
  const auto detected = apply_cross_constraint(det.detect(frames[0].image), cross);
  ev.detected = static_cast<int>(detected.size());

  // Follow only the lines that start on a true edge; remember their truth id and frame-0 pose.
  std::vector<LineSegment> lines, initial;
  std::vector<int> truth_id;
  std::vector<bool> clipped;  // cut at the border once: its endpoints no longer follow the motion
  for (const auto& s : detected) {
    const int id = truth_id_of(s, frames[0].truth, tolerance_px);
    if (id < 0) continue;
    LineSegment l = s;
    l.id = static_cast<int>(lines.size());
    lines.push_back(l);
    initial.push_back(l);
    truth_id.push_back(id);
    clipped.push_back(false);
  }
  ev.on_truth = static_cast<int>(lines.size());
  ev.kept_per_frame.push_back(ev.on_truth);

  OpticalFlowPyramid prev = tracker.make_pyramid(frames[0].image);
  for (size_t k = 1; k < frames.size(); ++k) {
    OpticalFlowPyramid next = tracker.make_pyramid(frames[k].image);
    const auto tracks = tracker.track(prev, next, lines);
    std::vector<LineSegment> kept;
    for (const auto& tr : tracks) {
      if (tr.status != TrackStatus::Tracked) continue;
      kept.push_back(tr.line);
      const int n = tr.line.id;
      if (const LineSegment* t = find_truth(frames[k].truth, truth_id[n])) {
        ev.normal_errors.push_back(point_segment_distance(tr.line.start, *t));
        ev.normal_errors.push_back(point_segment_distance(tr.line.end, *t));
      }
      if (tr.clipped) clipped[n] = true;
      if (motions && !clipped[n]) {
        const Eigen::Isometry2d m = (*motions)[k] * (*motions)[0].inverse();
        ev.endpoint_errors.push_back((tr.line.start - m * initial[n].start).norm());
        ev.endpoint_errors.push_back((tr.line.end - m * initial[n].end).norm());
      }
    }
    lines = std::move(kept);
    ev.kept_per_frame.push_back(static_cast<int>(lines.size()));
    prev = std::move(next);
  }
  return ev;
}

}  // namespace pllvo::lines
