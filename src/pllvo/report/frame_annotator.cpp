#include "pllvo/report/frame_annotator.h"

#include <cstdio>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "pllvo/common/error.h"

namespace pllvo::report {

cv::Mat annotate(const vo::TrackingView& view, const AnnotationStyle& style) {
  cv::Mat out;
  if (view.image.empty()) return out;
  if (view.image.channels() == 1)
    cv::cvtColor(view.image, out, cv::COLOR_GRAY2BGR);
  else
    out = view.image.clone();
  int map_points = 0, map_lines = 0;
  for (const auto& l : view.lines) {
    const bool mapped = l.line != vo::kNoId;
    map_lines += mapped;
    cv::line(out, cv::Point2d(l.segment.start.x(), l.segment.start.y()),
             cv::Point2d(l.segment.end.x(), l.segment.end.y()), mapped ? style.map_line : style.candidate_line,
             style.line_thickness, cv::LINE_AA);
  }
  for (const auto& p : view.points) {
    const bool mapped = p.point != vo::kNoId;
    map_points += mapped;
    cv::circle(out, p.px, style.point_radius, mapped ? style.map_point : style.candidate_point, -1, cv::LINE_AA);
  }
  if (style.caption) {
    char text[160];
    std::snprintf(text, sizeof text, "frame %zu  %s  points %zu (%d map)  lines %zu (%d map)", view.frame_index,
                  view.tracked ? "tracked" : "NOT TRACKED", view.points.size(), map_points, view.lines.size(),
                  map_lines);
    cv::rectangle(out, cv::Rect(0, 0, out.cols, 20), cv::Scalar(0, 0, 0), -1);
    cv::putText(out, text, cv::Point(6, 14), cv::FONT_HERSHEY_SIMPLEX, 0.45,
                view.tracked ? cv::Scalar(255, 255, 255) : cv::Scalar(80, 80, 255), 1, cv::LINE_AA);
  }
  return out;
}

FrameSnapshots::FrameSnapshots(std::filesystem::path dir, size_t first_frame, size_t frames, size_t count,
                               size_t patience)
    : dir_(std::move(dir)), patience_(patience) {
  // Targets at the middle of `count` equal parts, so neither the start (initialisation) nor
  // the last frame is favoured.
  for (size_t k = 0; k < count && frames > 0; ++k)
    targets_.push_back(first_frame + static_cast<size_t>((k + 0.5) * frames / count));
}

void FrameSnapshots::operator()(const vo::TrackingView& view) {
  if (next_ >= targets_.size() || view.frame_index < targets_[next_]) return;
  const bool late = view.frame_index >= targets_[next_] + patience_;
  if (!view.tracked && !late) return;
  std::filesystem::create_directories(dir_);
  const auto path = dir_ / ("frame_" + std::to_string(view.frame_index) + ".png");
  const cv::Mat image = annotate(view);
  if (!image.empty() && !cv::imwrite(path.string(), image)) throw InputError(path, "cannot write the image");
  written_.push_back(path);
  while (next_ < targets_.size() && targets_[next_] <= view.frame_index) ++next_;
}

}  // namespace pllvo::report
