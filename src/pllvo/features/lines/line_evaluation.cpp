#include "pllvo/features/lines/line_evaluation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

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
    c.ours.add(score_line_detections(ours.detect(f.image), f, score));
    c.edlines.add(
        score_line_detections(detect_edlines_plain(f.image, EdgeDrawingConfig::opencv_defaults()), f, score));
    const auto lsd = detect_lsd(f.image);
    c.lsd.add(score_line_detections(lsd, f, score));
    std::vector<LineSegment> long_lsd;
    for (const auto& s : lsd)
      if (s.length() >= detector.min_length_px) long_lsd.push_back(s);
    c.lsd_min_length.add(score_line_detections(long_lsd, f, score));
  }
  return c;
}

double TrackingEvaluation::kept_share() const {
  return on_truth > 0 && !kept_per_frame.empty() ? static_cast<double>(kept_per_frame.back()) / on_truth : 0.0;
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

double SynthTrackingEvaluation::kept_share(int j) const {
  if (j < 1 || j >= static_cast<int>(tracked.size()) || tracked[j - 1] == 0) return 0.0;
  return static_cast<double>(tracked[j]) / tracked[j - 1];
}

namespace {
// Pooled over the steps: lines kept at the steps / lines entering them.
double pooled_share(const std::vector<long>& kept, const std::vector<long>& lost_outside) {
  double in = 0.0, out = 0.0;
  for (size_t j = 1; j < kept.size(); ++j) {
    in += static_cast<double>(kept[j - 1] - (lost_outside.empty() ? 0 : lost_outside[j] - lost_outside[j - 1]));
    out += static_cast<double>(kept[j]);
  }
  return in > 0 ? out / in : 0.0;
}
}  // namespace

double SynthTrackingEvaluation::kept_share_per_frame() const { return pooled_share(tracked, {}); }

double SynthTrackingEvaluation::kept_share_per_frame_in_image() const {
  return pooled_share(tracked, left_image);
}

std::vector<double> SynthTrackingEvaluation::all_endpoint_errors() const {
  std::vector<double> all;
  for (size_t j = 1; j < endpoint_errors.size(); ++j)
    all.insert(all.end(), endpoint_errors[j].begin(), endpoint_errors[j].end());
  return all;
}

SynthTrackingEvaluation evaluate_synth_tracking(const SynthLineSequence& seq, const LineDetectorConfig& detector,
                                                const CrossConstraintConfig& cross,
                                                const LineTrackerConfig& tracker_config, int chain_length,
                                                const DetectionScoreConfig& score) {
  SynthTrackingEvaluation ev;
  ev.chain_length = std::max(chain_length, 1);
  const size_t L = static_cast<size_t>(ev.chain_length);
  ev.tracked.assign(L + 1, 0);
  ev.left_image.assign(L + 1, 0);
  ev.endpoint_errors.assign(L + 1, {});
  LineDetector det(detector);
  const LineTracker tracker(tracker_config);
  for (size_t s = 0; s + L < seq.frames.size(); s += L) {
    const auto detected = apply_cross_constraint(det.detect(seq.frames[s].image), cross);
    ev.detected += static_cast<long>(detected.size());
    struct Followed {
      int start_id, end_id;  // 3-D edge of each endpoint
      Eigen::Vector3d X_start, X_end;
      bool has_truth, clipped = false;
    };
    std::vector<Followed> followed;
    std::vector<LineSegment> lines;
    const auto& truth0 = seq.frames[s].truth;
    for (const auto& d : detected) {
      const TruthMatch m = match_detection(d, truth0, score);
      if (!m.correct) continue;
      Followed f{truth0[m.start_piece].id, truth0[m.end_piece].id, {}, {}, false};
      f.has_truth = seq.edge_point(s, f.start_id, d.start, f.X_start) && seq.edge_point(s, f.end_id, d.end, f.X_end);
      Eigen::Vector2d a, b;
      if (f.has_truth && seq.project(s, f.X_start, a) && seq.project(s, f.X_end, b)) {
        ev.endpoint_errors[0].push_back((d.start - a).norm());
        ev.endpoint_errors[0].push_back((d.end - b).norm());
      }
      LineSegment l = d;
      l.id = static_cast<int>(followed.size());
      followed.push_back(f);
      lines.push_back(l);
    }
    ev.started += static_cast<long>(lines.size());
    ev.tracked[0] += static_cast<long>(lines.size());
    OpticalFlowPyramid prev = tracker.make_pyramid(seq.frames[s].image);
    long left = 0;
    for (size_t j = 1; j <= L; ++j) {
      const size_t k = s + j;
      OpticalFlowPyramid next = tracker.make_pyramid(seq.frames[k].image);
      std::vector<LineSegment> kept;
      for (const auto& tr : tracker.track(prev, next, lines)) {
        if (tr.status == TrackStatus::OutOfImage) ++left;
        if (tr.status != TrackStatus::Tracked) continue;
        kept.push_back(tr.line);
        Followed& f = followed[tr.line.id];
        if (tr.clipped) f.clipped = true;
        const auto& truth = seq.frames[k].truth;
        for (const auto& [p, id] : {std::pair{tr.line.start, f.start_id}, std::pair{tr.line.end, f.end_id}}) {
          double d = -1;
          for (const auto& t : truth)
            if (t.id == id && (d < 0 || point_segment_distance(p, t) < d)) d = point_segment_distance(p, t);
          if (d >= 0) ev.normal_errors.push_back(d);
        }
        Eigen::Vector2d a, b;
        if (f.has_truth && !f.clipped && seq.project(k, f.X_start, a) && seq.project(k, f.X_end, b)) {
          ev.endpoint_errors[j].push_back((tr.line.start - a).norm());
          ev.endpoint_errors[j].push_back((tr.line.end - b).norm());
        }
      }
      lines = std::move(kept);
      ev.tracked[j] += static_cast<long>(lines.size());
      ev.left_image[j] += left;
      prev = std::move(next);
    }
  }
  return ev;
}

}  // namespace pllvo::lines
