#pragma once
// Frame-to-frame pyramidal Lucas-Kanade tracking with a forward-backward check.
// Each frame's pyramid is built once and serves as "next" for one step and "previous"
// for the following one.
#include <vector>

#include <opencv2/core.hpp>

#include "pllvo/vo/vo_config.h"

namespace pllvo::vo {

/// Image pyramid with gradients in cv::buildOpticalFlowPyramid's layout.
struct ImagePyramid {
  cv::Mat image;
  std::vector<cv::Mat> levels;
  bool empty() const { return levels.empty(); }
  cv::Size size() const { return image.size(); }
};

struct TrackResult {
  std::vector<cv::Point2f> points;  ///< positions in the target image (valid where ok)
  std::vector<unsigned char> ok;    ///< tracked, inside the image and passed the FB check
  std::vector<float> fb_error;      ///< forward-backward distance in pixels (inf when not tracked)
  int tracked() const;
};

class PointTracker {
 public:
  explicit PointTracker(const KltConfig& config);

  ImagePyramid build_pyramid(const cv::Mat& image) const;

  /// Tracks `points` of `from` into `to`. `predicted` (same size) seeds the search, e.g. the
  /// projection of a 3-D point under the motion prior; without it the search starts in place.
  TrackResult track(const ImagePyramid& from, const ImagePyramid& to, const std::vector<cv::Point2f>& points,
                    const std::vector<cv::Point2f>* predicted = nullptr) const;

 private:
  KltConfig config_;
  cv::Size window_;
  cv::TermCriteria criteria_;
};

/// Normalised cross-correlation of the size x size patches around two sub-pixel points;
/// insensitive to gain and offset, so it holds across exposure changes.
double patch_ncc(const cv::Mat& a, cv::Point2f pa, const cv::Mat& b, cv::Point2f pb, int size = 9);

}  // namespace pllvo::vo
