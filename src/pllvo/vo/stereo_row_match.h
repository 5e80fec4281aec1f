#pragma once
// Left-right point matches of a rectified pair, finished along the row. 2-D Lucas-Kanade
// (PointTracker) may slide along an edge; on a near-horizontal edge a slide of a fraction of a
// pixel in y, well inside the epipolar check, moves x by pixels, and the stereo depth is wrong
// (docs/vo.md: ceiling-edge points of one depth got disparities of 16 to 28 px).
// The rectified geometry fixes y, so x is solved in 1-D with y held at the left row, and a
// window whose texture has too little horizontal gradient to fix x is rejected.
#include <optional>

#include <opencv2/core.hpp>

namespace pllvo::vo {

struct StereoRowMatchConfig {
  int window_px = 21;  ///< square window side (odd)
  /// Share of horizontal gradient energy in the left window, sum(Ix^2) / sum(Ix^2 + Iy^2),
  /// below which x is not fixed by the texture (a horizontal edge: ~0; a corner: ~0.5).
  double min_horizontal_share = 0.03;
  /// The 1-D solution may move x by at most this far from the 2-D one (pixels).
  double max_shift_px = 3.0;
  int max_iterations = 10;
};

/// x in `right` (CV_8U, rectified) of the left pixel `left_px`, refined in 1-D along the row
/// from `right_x`; nullopt when the window lacks horizontal texture, leaves the image, or the
/// refinement does not converge within max_shift_px.
std::optional<float> refine_along_row(const cv::Mat& left, const cv::Mat& right, const cv::Point2f& left_px,
                                      float right_x, const StereoRowMatchConfig& config = {});

}  // namespace pllvo::vo
