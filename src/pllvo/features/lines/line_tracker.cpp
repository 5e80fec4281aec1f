#include "pllvo/features/lines/line_tracker.h"

#include <algorithm>
#include <cmath>

#include <opencv2/video/tracking.hpp>

#include "pllvo/common/error.h"
#include "pllvo/common/statistics.h"

namespace pllvo::lines {

namespace {
/// Smaller over larger eigenvalue of the structure tensor of the window_px x window_px window
/// around `p`, from the pyramid's level-0 derivatives (CV_16SC2); 0 on a flat window.
double eigen_ratio(const cv::Mat& derivatives, const cv::Point2f& p, int window_px) {
  const int half = window_px / 2;
  const int cx = cvRound(p.x), cy = cvRound(p.y);
  const int x0 = std::max(0, cx - half), x1 = std::min(derivatives.cols - 1, cx + half);
  const int y0 = std::max(0, cy - half), y1 = std::min(derivatives.rows - 1, cy + half);
  double a = 0.0, b = 0.0, c = 0.0;
  for (int y = y0; y <= y1; ++y) {
    const auto* row = derivatives.ptr<cv::Vec2s>(y);
    for (int x = x0; x <= x1; ++x) {
      const double dx = row[x][0], dy = row[x][1];
      a += dx * dx, b += dx * dy, c += dy * dy;
    }
  }
  return structure_tensor_ratio(a, b, c);
}
}  // namespace

void LineTrackerConfig::load(const ConfigNode& node) {
  node.get("window_px", window_px);
  node.get("max_pyramid_level", max_pyramid_level);
  node.get("max_iterations", max_iterations);
  node.get("epsilon_px", epsilon_px);
  node.get("min_eigen_threshold", min_eigen_threshold);
  node.get("normalized_mean", normalized_mean);
  node.get("sample_spacing_px", sample_spacing_px);
  node.get("min_samples", min_samples);
  node.get("max_samples", max_samples);
  node.get("end_margin_px", end_margin_px);
  node.get("aperture_max_eigen_ratio", aperture_max_eigen_ratio);
  fit.load(node.child("fit"));
  node.get("min_inlier_ratio", min_inlier_ratio);
  node.get("max_residual_px", max_residual_px);
  node.get("max_length_change", max_length_change);
  node.get("border_px", border_px);
  node.get("min_visible_ratio", min_visible_ratio);
  node.reject_unknown_keys();
  if (window_px < 3) throw InputError(node.file(), node.path("window_px"), "must be >= 3");
  if (max_pyramid_level < 0) throw InputError(node.file(), node.path("max_pyramid_level"), "must be >= 0");
  if (normalized_mean < 0.0 || normalized_mean > 255.0)
    throw InputError(node.file(), node.path("normalized_mean"), "must be in [0, 255] (0 = off)");
  if (sample_spacing_px <= 0.0) throw InputError(node.file(), node.path("sample_spacing_px"), "must be > 0");
  if (min_samples < 2 || max_samples < min_samples)
    throw InputError(node.file(), node.path("min_samples"), "need 2 <= min_samples <= max_samples");
  if (aperture_max_eigen_ratio < 0.0 || aperture_max_eigen_ratio >= 1.0)
    throw InputError(node.file(), node.path("aperture_max_eigen_ratio"), "must be in [0, 1) (0 = off)");
  if (min_visible_ratio < 0.0 || min_visible_ratio > 1.0)
    throw InputError(node.file(), node.path("min_visible_ratio"), "must be in [0, 1]");
  if (min_inlier_ratio < 0.0 || min_inlier_ratio > 1.0)
    throw InputError(node.file(), node.path("min_inlier_ratio"), "must be in [0, 1]");
}

const char* to_string(TrackStatus s) {
  switch (s) {
    case TrackStatus::Tracked: return "tracked";
    case TrackStatus::FewInliers: return "few-inliers";
    case TrackStatus::LargeResidual: return "large-residual";
    case TrackStatus::LengthChange: return "length-change";
    case TrackStatus::OutOfImage: return "out-of-image";
  }
  return "?";
}

LineTracker::LineTracker(LineTrackerConfig config) : config_(std::move(config)) {}

OpticalFlowPyramid LineTracker::make_pyramid(const cv::Mat& gray) const {
  return OpticalFlowPyramid(gray, cv::Size(config_.window_px, config_.window_px), config_.max_pyramid_level,
                            config_.normalized_mean);
}

std::vector<double> LineTracker::sample_fractions(const LineSegment& line) const {
  const double len = line.length();
  const double usable = std::max(0.0, len - 2.0 * config_.end_margin_px);
  int n = static_cast<int>(std::floor(usable / config_.sample_spacing_px)) + 1;
  n = std::clamp(n, config_.min_samples, config_.max_samples);
  std::vector<double> t(n);
  const double t0 = len > 0 ? std::min(0.5, config_.end_margin_px / len) : 0.5;
  for (int i = 0; i < n; ++i) t[i] = t0 + (1.0 - 2.0 * t0) * i / (n - 1);
  return t;
}

std::vector<LineTrack> LineTracker::track(const OpticalFlowPyramid& prev, const OpticalFlowPyramid& next,
                                          const std::vector<LineSegment>& lines,
                                          const std::vector<LineSegment>* predicted) const {
  if (prev.empty() || next.empty() || prev.image_size() != next.image_size())
    throw InputError("line tracking: the two pyramids must be built and of the same image size");
  if (prev.window().width < config_.window_px || next.window().width < config_.window_px)
    throw InputError("line tracking: pyramids built for a smaller window than the tracker's (use make_pyramid)");
  if (predicted && predicted->size() != lines.size())
    throw InputError("line tracking: one predicted line per line is required");

  // All samples of all lines in one LK call.
  std::vector<int> first(lines.size() + 1, 0);
  std::vector<cv::Point2f> p0, p1;
  for (size_t i = 0; i < lines.size(); ++i) {
    const auto fractions = sample_fractions(lines[i]);
    first[i + 1] = first[i] + static_cast<int>(fractions.size());
    for (const double t : fractions) {
      const Eigen::Vector2d p = lines[i].at(t), guess = predicted ? (*predicted)[i].at(t) : p;
      p0.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()));
      p1.emplace_back(static_cast<float>(guess.x()), static_cast<float>(guess.y()));
    }
  }
  std::vector<uchar> status;
  std::vector<float> err;
  if (!p0.empty()) {
    const int level = std::min({config_.max_pyramid_level, prev.max_level(), next.max_level()});
    cv::calcOpticalFlowPyrLK(prev.levels(), next.levels(), p0, p1, status, err,
                             cv::Size(config_.window_px, config_.window_px), level,
                             cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, config_.max_iterations,
                                              config_.epsilon_px),
                             predicted ? cv::OPTFLOW_USE_INITIAL_FLOW : 0, config_.min_eigen_threshold);
  }

  std::vector<LineTrack> tracks(lines.size());
  std::vector<Eigen::Vector2d> before, after;
  for (size_t i = 0; i < lines.size(); ++i) {
    LineTrack& tr = tracks[i];
    tr.line = lines[i];
    tr.samples = first[i + 1] - first[i];
    before.clear();
    after.clear();
    for (int k = first[i]; k < first[i + 1]; ++k) {
      if (!status[k] || !std::isfinite(p1[k].x) || !std::isfinite(p1[k].y)) continue;
      before.emplace_back(p0[k].x, p0[k].y);
      after.emplace_back(p1[k].x, p1[k].y);
    }
    if (config_.aperture_max_eigen_ratio > 0.0 && !before.empty())
      tr.aperture_samples = settle_aperture_samples(prev.levels()[1], lines[i], before, after);
    const int need = static_cast<int>(std::ceil(config_.min_inlier_ratio * tr.samples));
    if (static_cast<int>(before.size()) < std::max(2, need)) continue;  // FewInliers
    const LineMotionFit fit = fit_line_motion(lines[i], before, after, config_.fit);
    tr.inliers = fit.inliers;
    if (!fit.valid || fit.inliers < std::max(2, need)) continue;
    tr.motion = fit.motion;
    tr.rms_normal_px = fit.rms_normal_px;
    tr.stretch = fit.stretch;
    tr.line = fit.motion.apply(lines[i]);
    if (fit.rms_normal_px > config_.max_residual_px) {
      tr.status = TrackStatus::LargeResidual;
    } else if (std::abs(fit.stretch - 1.0) > config_.max_length_change) {
      tr.status = TrackStatus::LengthChange;
    } else {
      const cv::Size size = next.image_size();
      const Eigen::Vector2d lo(config_.border_px, config_.border_px);
      const Eigen::Vector2d hi(size.width - 1 - config_.border_px, size.height - 1 - config_.border_px);
      const double full = tr.line.length();
      LineSegment visible = tr.line;
      if (!clip_to_rect(visible, lo, hi) || visible.length() < config_.min_visible_ratio * full) {
        tr.status = TrackStatus::OutOfImage;
      } else {
        tr.clipped = visible.length() < full - 1e-9;
        tr.line = visible;
        tr.status = TrackStatus::Tracked;
      }
    }
  }
  return tracks;
}

int LineTracker::settle_aperture_samples(const cv::Mat& derivatives, const LineSegment& line,
                                         const std::vector<Eigen::Vector2d>& before,
                                         std::vector<Eigen::Vector2d>& after) const {
  const Eigen::Vector2d t = line.direction(), n = line.normal();
  std::vector<double> along;
  for (size_t k = 0; k < before.size(); ++k) along.push_back(t.dot(after[k] - before[k]));
  const double median_along = median(along);
  int settled = 0;
  for (size_t k = 0; k < before.size(); ++k) {
    const cv::Point2f p(static_cast<float>(before[k].x()), static_cast<float>(before[k].y()));
    if (eigen_ratio(derivatives, p, config_.window_px) >= config_.aperture_max_eigen_ratio) continue;
    after[k] = before[k] + n * n.dot(after[k] - before[k]) + t * median_along;
    ++settled;
  }
  return settled;
}

std::vector<LineSegment> tracked_lines(const std::vector<LineTrack>& tracks) {
  std::vector<LineSegment> out;
  for (const auto& t : tracks)
    if (t.status == TrackStatus::Tracked) out.push_back(t.line);
  return out;
}

}  // namespace pllvo::lines
