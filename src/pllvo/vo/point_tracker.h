#pragma once
// Frame-to-frame pyramidal Lucas-Kanade tracking with a forward-backward check.
// Each frame's pyramid is built once and serves as "next" for one step and "previous"
// for the following one.
#include <vector>

#include <opencv2/core.hpp>

#include "pllvo/features/lines/optical_flow_pyramid.h"
#include "pllvo/vo/vo_config.h"

namespace pllvo::vo {

/// One frame's image with its optical-flow pyramid (gradients included), shared by the point
/// tracker and the line tracker: built once, for the larger of their windows and levels.
struct ImagePyramid {
  cv::Mat image;
  lines::OpticalFlowPyramid flow;
  bool empty() const { return flow.empty(); }
  cv::Size size() const { return image.size(); }
  const std::vector<cv::Mat>& levels() const { return flow.levels(); }
};

struct TrackResult {
  std::vector<cv::Point2f> points;  ///< positions in the target image (valid where ok)
  std::vector<unsigned char> ok;    ///< tracked, inside the image, passed the FB and NCC checks
  std::vector<float> fb_error;      ///< forward-backward distance in pixels (inf when not tracked)
  /// Why the others were dropped, one reason each, in the order checked: LK found no match
  /// (either direction), the match left the image border, the forward-backward check, the
  /// NCC appearance check. In low light and on faint texture this says which check to look at.
  struct Rejections {
    int lk = 0, border = 0, forward_backward = 0, appearance = 0;
  } rejected;
  /// The result of track_with_contrast_fallback's second try on local contrast was weighed.
  bool contrast_retried = false;
  int tracked() const;
};

class PointTracker {
 public:
  explicit PointTracker(const KltConfig& config);

  /// Pyramid for this tracker, padded for a window of at least `min_window` pixels and with
  /// at least `min_levels` levels above the base (so that another tracker can share it).
  ImagePyramid build_pyramid(const cv::Mat& image, int min_window = 0, int min_levels = 0) const;

  /// Tracks `points` of `from` into `to`. `predicted` (same size) seeds the search, e.g. the
  /// projection of a 3-D point under the motion prior; without it the search starts in place.
  TrackResult track(const ImagePyramid& from, const ImagePyramid& to, const std::vector<cv::Point2f>& points,
                    const std::vector<cv::Point2f>* predicted = nullptr) const;

  /// As track(); when fewer than klt.contrast_fallback_share of the points survive (a flicker
  /// or exposure step that one gain per frame does not remove), tracks them again on locally
  /// contrast-normalised images (local_contrast) and returns whichever result follows more.
  /// Every frame-to-frame hop of the odometry goes through it: the map's tracks, the tracker's
  /// corners, the keyframe catch-up and the monocular start.
  TrackResult track_with_contrast_fallback(const ImagePyramid& from, const ImagePyramid& to,
                                           const std::vector<cv::Point2f>& points,
                                           const std::vector<cv::Point2f>* predicted = nullptr) const;

  /// Moves each of `positions` (in `to`, e.g. where a frame-to-frame track ended) onto the patch
  /// of its `reference` point in `from` by one LK alignment over `levels` pyramid levels above
  /// the base. A point is aligned (ok) when LK converges within `max_shift_px` of where it
  /// started; the others keep their position. One alignment against a fixed reference carries
  /// its own error only, where a frame-to-frame track adds up the error of every step.
  /// `from`: the reference image's pyramid levels, with or without derivatives (reference_levels()).
  std::vector<unsigned char> align(const std::vector<cv::Mat>& from, const ImagePyramid& to,
                                   const std::vector<cv::Point2f>& reference, std::vector<cv::Point2f>& positions,
                                   int levels, double max_shift_px) const;
  /// An image's pyramid for align(): `levels` levels above the base, padded for this tracker's
  /// window, without derivatives (a fifth of an ImagePyramid's memory; LK derives them itself).
  std::vector<cv::Mat> reference_levels(const cv::Mat& image, int levels) const;

 private:
  KltConfig config_;
  cv::Size window_;
  cv::TermCriteria criteria_;
};

/// The image with its local mean removed and its local contrast scaled to a fixed level
/// (window x window box statistics), as 8-bit around 128: what stays when light changes
/// unevenly across the image.
cv::Mat local_contrast(const cv::Mat& image, int window);

/// Standard deviation of the image's pixel noise in grey levels, from the mean absolute
/// response to a 3x3 operator that cancels locally linear intensity (Immerkaer 1996), over
/// the central half of the image (edges of the scene raise it a little; flat noise dominates).
double estimate_noise_sigma(const cv::Mat& image);

/// Normalised cross-correlation of the size x size patches around two sub-pixel points;
/// insensitive to gain and offset, so it holds across exposure changes.
double patch_ncc(const cv::Mat& a, cv::Point2f pa, const cv::Mat& b, cv::Point2f pb, int size = 9);

/// lines::structure_tensor_ratio of the size x size window around a sub-pixel point of `image`
/// (central differences; for detections, which have no pyramid derivatives yet).
double corner_ratio(const cv::Mat& image, cv::Point2f p, int size);

}  // namespace pllvo::vo
