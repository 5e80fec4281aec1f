#include "pllvo/features/lines/line_fit.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pllvo::lines {

LineFit fit_line_tls(const std::vector<Eigen::Vector2d>& points) {
  LineFit fit;
  fit.count = static_cast<int>(points.size());
  if (points.empty()) return fit;
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  for (const auto& p : points) c += p;
  c /= static_cast<double>(points.size());
  double sxx = 0, sxy = 0, syy = 0;
  for (const auto& p : points) {
    const Eigen::Vector2d d = p - c;
    sxx += d.x() * d.x();
    sxy += d.x() * d.y();
    syy += d.y() * d.y();
  }
  fit.centroid = c;
  // Principal axis of the 2x2 scatter matrix in closed form.
  const double theta = 0.5 * std::atan2(2.0 * sxy, sxx - syy);
  fit.direction = Eigen::Vector2d(std::cos(theta), std::sin(theta));
  if (points.size() >= 2) {
    const Eigen::Vector2d n(-fit.direction.y(), fit.direction.x());
    double ss = 0;
    for (const auto& p : points) ss += std::pow(n.dot(p - c), 2);
    fit.rms_distance = std::sqrt(ss / static_cast<double>(points.size()));
  }
  return fit;
}

LineSegment segment_from_fit(const LineFit& fit, const std::vector<Eigen::Vector2d>& points) {
  double tmin = std::numeric_limits<double>::max(), tmax = std::numeric_limits<double>::lowest();
  for (const auto& p : points) {
    const double t = fit.direction.dot(p - fit.centroid);
    tmin = std::min(tmin, t);
    tmax = std::max(tmax, t);
  }
  if (points.empty()) tmin = tmax = 0.0;
  return LineSegment(fit.centroid + tmin * fit.direction, fit.centroid + tmax * fit.direction);
}

LineSegment segment_from_fit(const LineFit& fit, const std::vector<Eigen::Vector2d>& points,
                             const LineSegment& reference) {
  LineSegment s = segment_from_fit(fit, points);
  if ((s.end - s.start).dot(reference.end - reference.start) < 0.0) std::swap(s.start, s.end);
  s.id = reference.id;
  s.response = reference.response;
  return s;
}

}  // namespace pllvo::lines
