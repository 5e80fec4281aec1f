#pragma once
// EDLines line detection on top of OpenCV's ximgproc::EdgeDrawing, plus what the VO needs on top:
//   1. pre-filtering chosen from the frame's brightness and noise (image_prefilter.h);
//   2. merging of collinear EDLines pieces (angle, perpendicular distance and gap thresholds);
//   3. sub-pixel refinement of each merged segment long enough to be kept: the edge pixels in a
//      band along it, each moved to the gradient-magnitude peak across the edge (parabola through
//      three gradient samples), are fitted by total least squares, and the endpoints are the
//      extreme pixels projected on the fitted line;
//   4. a minimum length, a minimum edge strength and an optional cap on the number of lines.
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "pllvo/common/yaml_config.h"
#include "pllvo/features/lines/image_prefilter.h"
#include "pllvo/features/lines/line_segment.h"

namespace cv::ximgproc {
class EdgeDrawing;
}

namespace pllvo::lines {

/// Settings handed to cv::ximgproc::EdgeDrawing (names follow its Params).
struct EdgeDrawingConfig {
  std::string gradient_operator = "prewitt";  ///< prewitt | sobel | scharr | lsd
  int gradient_threshold = 20;                ///< on clean frames; the prefilter may raise it
  int anchor_threshold = 0;
  int scan_interval = 1;
  int min_path_length = 10;
  double sigma = 1.0;  ///< Gaussian sigma on clean frames; the prefilter may raise it
  bool sum_flag = true;
  /// EDLines' a-contrario (NFA) validation. Off by default: with the minimum length and the
  /// minimum edge strength below it removes almost nothing more (EuRoC: 192 vs 194 lines,
  /// synthetic precision 0.966 vs 0.953) and costs ~1.5 ms per 752x480 frame (docs/lines.md).
  bool nfa_validation = false;
  /// EDLines' own minimum (pixels of a chain); -1 = derived from the image size by EDLines.
  int min_line_length = -1;
  double line_fit_error_threshold = 1.0;
  double max_distance_between_two_lines = 6.0;
  double max_error_threshold = 1.3;

  void load(const ConfigNode& node);
  /// OpenCV's own EdgeDrawing defaults (NFA validation on): the "plain EdgeDrawing" baseline.
  static EdgeDrawingConfig opencv_defaults();
};

struct LineDetectorConfig {
  PrefilterConfig prefilter;
  EdgeDrawingConfig edge_drawing;
  /// Sub-pixel refit of every segment to its edge pixels (off: EDLines' endpoints as they are).
  bool subpixel_refinement = true;
  /// Edge pixels farther than this from a segment (px) do not support it in the refinement.
  double support_distance_px = 1.5;
  /// ...and edge pixels whose image gradient (3x3 Sobel) points more than this angle away from
  /// the segment's normal do not support it either: at a corner or a junction the edge map
  /// turns onto the other edge, whose pixels inside the band would otherwise stretch the
  /// segment past the corner (0 = no direction check).
  double support_max_angle_deg = 45.0;
  /// Collinear pieces are merged when their directions differ by at most this angle...
  bool merge_collinear = true;
  double merge_max_angle_deg = 2.0;
  /// ...every endpoint of one lies within this distance of the other's line (px)...
  double merge_max_distance_px = 1.5;
  /// ...and the gap between them along the line is at most this (px; overlap counts as 0).
  double merge_max_gap_px = 8.0;
  /// Segments shorter than this (px) are dropped after merging.
  double min_length_px = 25.0;
  /// A segment is kept only when the mean gradient of its edge pixels is at least this multiple
  /// of EdgeDrawing's gradient threshold (as used on the frame): drops faint texture edges that
  /// happen to be straight (0 = off; needs subpixel_refinement, which measures the gradient).
  double min_gradient_ratio = 2.0;
  /// Keep at most this many lines, the longest first (0 = all).
  int max_lines = 0;

  void load(const ConfigNode& node);
};

/// Per-frame diagnostics of the last detect() call.
struct LineDetectionStats {
  PrefilterResult prefilter;  ///< without the image
  int edlines_count = 0;      ///< segments from EdgeDrawing
  int merged_count = 0;       ///< merges performed
  int output_count = 0;
};

class LineDetector {
 public:
  explicit LineDetector(LineDetectorConfig config = {});
  ~LineDetector();
  LineDetector(LineDetector&&) noexcept;
  LineDetector& operator=(LineDetector&&) noexcept;

  /// Detects lines in an 8-bit grayscale image. Ids are 0..n-1 in the output order (longest
  /// first). Throws InputError for an empty or non-8-bit-gray image.
  std::vector<LineSegment> detect(const cv::Mat& gray);

  const LineDetectorConfig& config() const { return config_; }
  const LineDetectionStats& last_stats() const { return stats_; }

 private:
  LineDetectorConfig config_;
  cv::Ptr<cv::ximgproc::EdgeDrawing> ed_;
  LineDetectionStats stats_;
};

/// Plain EdgeDrawing/EDLines with the given settings and nothing else (baseline for evaluation).
std::vector<LineSegment> detect_edlines_plain(const cv::Mat& gray, const EdgeDrawingConfig& config);

}  // namespace pllvo::lines
