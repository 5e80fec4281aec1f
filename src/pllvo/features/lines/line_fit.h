#pragma once
// Total-least-squares line fit: minimises the sum of squared perpendicular distances,
// so the fit is isotropic (unlike y = a + b x, which favours one image axis).
#include <vector>

#include <Eigen/Core>

#include "pllvo/features/lines/line_segment.h"

namespace pllvo::lines {

struct LineFit {
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  Eigen::Vector2d direction = Eigen::Vector2d::UnitX();  ///< unit
  double rms_distance = 0.0;  ///< RMS perpendicular distance of the points to the line
  int count = 0;
};

/// Fits a line to points (at least 2). Degenerate input keeps direction = x axis.
LineFit fit_line_tls(const std::vector<Eigen::Vector2d>& points);

/// Segment on the fitted line spanning the points' projections; start and end keep the
/// order of `reference` (start near reference.start) when one is given.
LineSegment segment_from_fit(const LineFit& fit, const std::vector<Eigen::Vector2d>& points);
LineSegment segment_from_fit(const LineFit& fit, const std::vector<Eigen::Vector2d>& points,
                             const LineSegment& reference);

}  // namespace pllvo::lines
