#include "pllvo/features/lines/line_segment.h"

#include <algorithm>
#include <cmath>

namespace pllvo::lines {

Eigen::Vector2d LineSegment::direction() const {
  const Eigen::Vector2d d = end - start;
  const double n = d.norm();
  return n > 0.0 ? Eigen::Vector2d(d / n) : Eigen::Vector2d::UnitX();
}

Eigen::Vector2d LineSegment::normal() const {
  const Eigen::Vector2d d = direction();
  return {-d.y(), d.x()};
}

double LineSegment::orientation() const {
  const Eigen::Vector2d d = end - start;
  double a = std::atan2(d.y(), d.x());
  if (a < 0.0) a += M_PI;
  if (a >= M_PI) a -= M_PI;
  return a;
}

double signed_line_distance(const Eigen::Vector2d& p, const LineSegment& s) {
  return s.normal().dot(p - s.start);
}

double project_along(const Eigen::Vector2d& p, const LineSegment& s) {
  return s.direction().dot(p - s.start);
}

double point_segment_distance(const Eigen::Vector2d& p, const LineSegment& s) {
  const Eigen::Vector2d d = s.end - s.start;
  const double len2 = d.squaredNorm();
  if (len2 <= 0.0) return (p - s.start).norm();
  const double t = std::clamp((p - s.start).dot(d) / len2, 0.0, 1.0);
  return (p - (s.start + t * d)).norm();
}

namespace {
double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

// Orientation of c relative to the directed line a->b: -1, 0 or +1.
int turn(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  const double v = cross(b - a, c - a);
  return (v > 0.0) - (v < 0.0);
}

bool within_box(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& p) {
  return p.x() >= std::min(a.x(), b.x()) && p.x() <= std::max(a.x(), b.x()) &&
         p.y() >= std::min(a.y(), b.y()) && p.y() <= std::max(a.y(), b.y());
}
}  // namespace

bool segments_intersect(const LineSegment& a, const LineSegment& b) {
  const int t1 = turn(a.start, a.end, b.start), t2 = turn(a.start, a.end, b.end);
  const int t3 = turn(b.start, b.end, a.start), t4 = turn(b.start, b.end, a.end);
  if (t1 != t2 && t3 != t4) return true;
  // Collinear touching cases.
  if (t1 == 0 && within_box(a.start, a.end, b.start)) return true;
  if (t2 == 0 && within_box(a.start, a.end, b.end)) return true;
  if (t3 == 0 && within_box(b.start, b.end, a.start)) return true;
  if (t4 == 0 && within_box(b.start, b.end, a.end)) return true;
  return false;
}

double segment_distance(const LineSegment& a, const LineSegment& b) {
  if (segments_intersect(a, b)) return 0.0;
  return std::min({point_segment_distance(a.start, b), point_segment_distance(a.end, b),
                   point_segment_distance(b.start, a), point_segment_distance(b.end, a)});
}

double acute_angle(const LineSegment& a, const LineSegment& b) {
  const double c = std::abs(a.direction().dot(b.direction()));
  return std::acos(std::min(1.0, c));
}

bool clip_to_rect(LineSegment& s, const Eigen::Vector2d& lo, const Eigen::Vector2d& hi) {
  const Eigen::Vector2d d = s.end - s.start;
  double t0 = 0.0, t1 = 1.0;
  for (int k = 0; k < 2; ++k) {
    // Inside means t * p <= q for both sides of the slab.
    const double p[2] = {-d[k], d[k]};
    const double q[2] = {s.start[k] - lo[k], hi[k] - s.start[k]};
    for (int side = 0; side < 2; ++side) {
      if (p[side] == 0.0) {
        if (q[side] < 0.0) return false;
      } else if (p[side] < 0.0) {
        t0 = std::max(t0, q[side] / p[side]);
      } else {
        t1 = std::min(t1, q[side] / p[side]);
      }
    }
  }
  if (t0 > t1) return false;
  const Eigen::Vector2d a = s.start + t0 * d, b = s.start + t1 * d;
  s.start = a;
  s.end = b;
  return true;
}

}  // namespace pllvo::lines
