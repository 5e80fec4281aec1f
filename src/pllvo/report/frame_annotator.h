#pragma once
// Tracked points and lines drawn on the tracker's working image, coloured by state: the
// picture behind `pllvo run --view` and the frames of a report page.
#include <filesystem>
#include <vector>

#include <opencv2/core.hpp>

#include "pllvo/vo/odometry.h"

namespace pllvo::report {

/// Colours (BGR) by state: map points green, candidate points yellow, map lines red, candidate
/// lines blue.
struct AnnotationStyle {
  cv::Scalar map_point{60, 200, 60};
  cv::Scalar candidate_point{0, 220, 255};
  cv::Scalar map_line{40, 40, 230};
  cv::Scalar candidate_line{230, 140, 30};
  int point_radius = 3;
  int line_thickness = 2;
  bool caption = true;  ///< frame index, state and counts in the top-left corner
};

/// A colour copy of `view.image` with the view's points and lines drawn on it.
cv::Mat annotate(const vo::TrackingView& view, const AnnotationStyle& style = {});

/// Writes a few annotated frames spread over a run to `dir/frame_<index>.png`: one near each
/// of `count` evenly spaced targets, the first tracked frame at or after the target (an
/// untracked one when tracking does not come back within `patience` frames).
class FrameSnapshots {
 public:
  FrameSnapshots(std::filesystem::path dir, size_t first_frame, size_t frames, size_t count, size_t patience = 20);
  void operator()(const vo::TrackingView& view);
  const std::vector<std::filesystem::path>& written() const { return written_; }

 private:
  std::filesystem::path dir_;
  std::vector<size_t> targets_;
  size_t next_ = 0;
  size_t patience_;
  std::vector<std::filesystem::path> written_;
};

}  // namespace pllvo::report
