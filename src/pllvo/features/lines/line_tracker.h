#pragma once
// Line optical-flow tracking (PLL-VO eq. 1-6): points sampled along each line of frame k are
// tracked to frame k+1 with pyramidal Lucas-Kanade (one batched call on shared pyramids), the
// line's rigid 2-D motion (g1, g2, g3) is fitted robustly to them (line_motion.h), and the
// tracked line is the moved segment. The same test rejects abnormal lines: a line is kept only
// when enough of its samples were tracked and agree with one rigid motion (share of inliers),
// when they agree closely (normal residual), and when the samples did not stretch or shrink
// along the line (length change), which happens when the "line" is not one physical edge.
#include <cstdint>
#include <string>
#include <vector>

#include "pllvo/common/yaml_config.h"
#include "pllvo/features/lines/line_motion.h"
#include "pllvo/features/lines/line_segment.h"
#include "pllvo/features/lines/optical_flow_pyramid.h"

namespace pllvo::lines {

struct LineTrackerConfig {
  // Pyramidal Lucas-Kanade.
  int window_px = 9;         ///< square LK window side
  int max_pyramid_level = 3; ///< 0 = full resolution only
  int max_iterations = 10;
  double epsilon_px = 0.01;  ///< LK stops when an update is smaller than this
  double min_eigen_threshold = 1e-4;  ///< cv::calcOpticalFlowPyrLK's minEigThreshold
  /// make_pyramid scales each frame to this mean grey level first, so LK's constant-brightness
  /// assumption holds under flicker and exposure changes (0 = off; see OpticalFlowPyramid). Off
  /// by default: re-quantising every frame costs LK accuracy on steadily lit frames
  /// (docs/lines.md), and a global gain does not undo lamps flickering against daylight.
  double normalized_mean = 0.0;
  // Sampling along each line.
  double sample_spacing_px = 10.0;
  int min_samples = 5;   ///< short lines still get this many samples
  int max_samples = 12;  ///< long lines get at most this many (evenly spread)
  double end_margin_px = 2.0;  ///< samples stay this far inside the endpoints (corners move oddly)
  /// Aperture problem: on a straight edge with flat sides LK fixes the motion across the edge
  /// but not along it, and its samples slide along the edge by different amounts, so a clean
  /// edge failed the tangential inlier gate or the length check. A sample whose LK window
  /// (in frame k) has a structure tensor with smaller / larger eigenvalue below this ratio keeps
  /// its motion across the line and takes, along the line, the median motion along the line of
  /// the line's tracked samples (0 = off: every sample's LK motion as it is).
  double aperture_max_eigen_ratio = 0.0;
  // Robust fit and acceptance.
  LineMotionFitConfig fit;
  double min_inlier_ratio = 0.7;   ///< inlier samples / samples
  double max_residual_px = 0.6;    ///< RMS normal residual of the inliers
  double max_length_change = 0.1;  ///< |stretch - 1|, see LineMotionFit::stretch
  /// The moved segment is clipped to the image shrunk by border_px; a line is lost when less
  /// than min_visible_ratio of its length stays inside.
  double border_px = 1.0;
  double min_visible_ratio = 0.5;

  void load(const ConfigNode& node);
};

enum class TrackStatus : uint8_t {
  Tracked,        ///< kept
  FewInliers,     ///< too few samples tracked by LK or consistent with one rigid motion
  LargeResidual,  ///< the inlier samples do not lie on one moved line
  LengthChange,   ///< the samples stretched or shrank along the line
  OutOfImage,     ///< less than min_visible_ratio of the moved segment stays in the image
};
const char* to_string(TrackStatus s);

struct LineTrack {
  LineSegment line;  ///< the moved segment in frame k+1 (id and response kept from frame k)
  bool clipped = false;  ///< `line` was cut at the image border
  LineMotion motion;
  TrackStatus status = TrackStatus::FewInliers;
  int samples = 0;
  int aperture_samples = 0;  ///< tracked samples whose motion along the line was replaced (aperture)
  int inliers = 0;
  double rms_normal_px = 0.0;
  double stretch = 1.0;
};

class LineTracker {
 public:
  explicit LineTracker(LineTrackerConfig config = {});

  /// A pyramid of `gray` matching this tracker's window and levels (build once per frame).
  OpticalFlowPyramid make_pyramid(const cv::Mat& gray) const;

  /// Tracks `lines` from frame k (`prev`) to frame k+1 (`next`): one LineTrack per line, in
  /// order. `predicted`, when given (same size as `lines`), is each line's expected position in
  /// frame k+1 (e.g. from a motion prior) and seeds LK; otherwise LK starts at zero motion.
  std::vector<LineTrack> track(const OpticalFlowPyramid& prev, const OpticalFlowPyramid& next,
                               const std::vector<LineSegment>& lines,
                               const std::vector<LineSegment>* predicted = nullptr) const;

  /// Where track() samples `line` (0: start, 1: end). A predicted line is sampled at the same
  /// fractions, so each sample's LK seed is its own point on the prediction, whatever the
  /// predicted length.
  std::vector<double> sample_fractions(const LineSegment& line) const;

  const LineTrackerConfig& config() const { return config_; }

 private:
  /// Replaces the motion along `line` of its aperture-limited samples (see
  /// aperture_max_eigen_ratio) by the median motion along it; returns how many it replaced.
  int settle_aperture_samples(const cv::Mat& derivatives, const LineSegment& line,
                              const std::vector<Eigen::Vector2d>& before, std::vector<Eigen::Vector2d>& after) const;

  LineTrackerConfig config_;
};

/// The moved segments of the tracks with status Tracked (abnormal lines dropped).
std::vector<LineSegment> tracked_lines(const std::vector<LineTrack>& tracks);

}  // namespace pllvo::lines
