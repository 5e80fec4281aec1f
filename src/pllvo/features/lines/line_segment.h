#pragma once
// A 2-D line segment in pixel coordinates and the planar geometry the line front end needs.
// Convention (OpenCV's): the centre of pixel (col, row) is the point (col, row).
#include <Eigen/Core>

namespace pllvo::lines {

struct LineSegment {
  Eigen::Vector2d start = Eigen::Vector2d::Zero();
  Eigen::Vector2d end = Eigen::Vector2d::Zero();
  /// Track id: kept by the tracker from frame to frame; -1 when not assigned.
  int id = -1;
  /// Detector strength: mean gradient magnitude of the supporting edge pixels (0 when unknown).
  double response = 0.0;

  LineSegment() = default;
  LineSegment(const Eigen::Vector2d& s, const Eigen::Vector2d& e, int id_ = -1, double response_ = 0.0)
      : start(s), end(e), id(id_), response(response_) {}

  double length() const { return (end - start).norm(); }
  Eigen::Vector2d midpoint() const { return 0.5 * (start + end); }
  /// Unit vector from start to end (x axis when the segment is degenerate).
  Eigen::Vector2d direction() const;
  /// Unit normal: direction rotated by +90 degrees.
  Eigen::Vector2d normal() const;
  /// Orientation of the undirected line in [0, pi).
  double orientation() const;
  /// Point at parameter t in [0, 1] from start to end.
  Eigen::Vector2d at(double t) const { return start + t * (end - start); }
};

/// Signed distance of p to the infinite line through the segment (positive on the normal's side).
double signed_line_distance(const Eigen::Vector2d& p, const LineSegment& s);
/// Euclidean distance of p to the closest point of the segment.
double point_segment_distance(const Eigen::Vector2d& p, const LineSegment& s);
/// Position of p's projection along the segment, in pixels from start (may be < 0 or > length).
double project_along(const Eigen::Vector2d& p, const LineSegment& s);
/// True when the two closed segments share a point.
bool segments_intersect(const LineSegment& a, const LineSegment& b);
/// Smallest distance between any point of a and any point of b (0 when they intersect).
double segment_distance(const LineSegment& a, const LineSegment& b);
/// Acute angle between the two undirected lines, in [0, pi/2].
double acute_angle(const LineSegment& a, const LineSegment& b);
/// Clips s to the axis-aligned rectangle [lo, hi] (Liang-Barsky), keeping its direction;
/// false (s unchanged) when no part of it lies inside.
bool clip_to_rect(LineSegment& s, const Eigen::Vector2d& lo, const Eigen::Vector2d& hi);

}  // namespace pllvo::lines
