#include "pllvo/features/lines/line_overlaps.h"

#include <algorithm>

namespace pllvo::lines {

std::vector<LineOverlap> find_overlaps(const std::vector<LineSegment>& lines, double overlap_distance_px) {
  struct Box {
    double x0, y0, x1, y1;
  };
  std::vector<Box> boxes(lines.size());
  for (size_t i = 0; i < lines.size(); ++i) {
    const auto& s = lines[i];
    boxes[i] = {std::min(s.start.x(), s.end.x()) - overlap_distance_px,
                std::min(s.start.y(), s.end.y()) - overlap_distance_px,
                std::max(s.start.x(), s.end.x()) + overlap_distance_px,
                std::max(s.start.y(), s.end.y()) + overlap_distance_px};
  }
  std::vector<LineOverlap> out;
  for (size_t i = 0; i < lines.size(); ++i) {
    for (size_t j = i + 1; j < lines.size(); ++j) {
      // Boxes grown by the distance on both sides: a necessary condition, with margin.
      if (boxes[i].x1 < boxes[j].x0 || boxes[j].x1 < boxes[i].x0 || boxes[i].y1 < boxes[j].y0 ||
          boxes[j].y1 < boxes[i].y0)
        continue;
      if (segment_distance(lines[i], lines[j]) > overlap_distance_px) continue;
      out.push_back({static_cast<int>(i), static_cast<int>(j), acute_angle(lines[i], lines[j])});
    }
  }
  return out;
}

}  // namespace pllvo::lines
