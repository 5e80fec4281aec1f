#pragma once
// Rigid 2-D motion of a line between two frames (PLL-VO eq. 1-6). A point (u, v) of the line
// whose start point is (u1, v1) moves to
//     u' = u + g1 - g3 (v - v1)
//     v' = v + g2 + g3 (u - u1)
// i.e. a translation (g1, g2) of the start point and a small rotation g3 (rad) about it. The
// model is linear in g = (g1, g2, g3), so the motion of a line follows from its tracked sample
// points by (weighted, robust) linear least squares.
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "pllvo/common/yaml_config.h"
#include "pllvo/features/lines/line_segment.h"

namespace pllvo::lines {

struct LineMotion {
  double g1 = 0.0;  ///< translation of the start point along u (px)
  double g2 = 0.0;  ///< translation of the start point along v (px)
  double g3 = 0.0;  ///< small rotation about the start point (rad)

  /// Moves point p of a line whose start point is `anchor` (eq. 6).
  Eigen::Vector2d apply(const Eigen::Vector2d& p, const Eigen::Vector2d& anchor) const {
    return {p.x() + g1 - g3 * (p.y() - anchor.y()), p.y() + g2 + g3 * (p.x() - anchor.x())};
  }
  /// The moved segment (both endpoints moved by eq. 6 about the segment's start).
  LineSegment apply(const LineSegment& s) const;
};

/// Robust fit settings. Residuals are split into the component across the line (normal) and
/// along it (tangential): optical flow on a straight edge is well defined across it but weakly
/// along it (aperture problem), so the two get their own Huber scales and inlier gates.
struct LineMotionFitConfig {
  double huber_normal_px = 0.5;
  double huber_tangential_px = 2.0;
  int irls_iterations = 5;
  /// A sample is an inlier when |normal residual| and |tangential residual| stay below these.
  double inlier_normal_px = 1.0;
  double inlier_tangential_px = 3.0;

  void load(const ConfigNode& node);
};

struct LineMotionFit {
  LineMotion motion;
  std::vector<uint8_t> inlier;  ///< per sample
  int inliers = 0;
  double rms_normal_px = 0.0;  ///< RMS normal residual of the inliers
  /// Stretch of the inlier samples along the line: least-squares slope of their positions along
  /// the moved line against their positions along the original line (1 = rigid).
  double stretch = 1.0;
  bool valid = false;  ///< false when fewer than 2 distinct inlier samples remain
};

/// Fits eq. 6 to samples `before` (on `line` in frame k) and their tracked positions `after`
/// (frame k+1): Huber-weighted IRLS from the least-squares start, then a plain least-squares
/// refit on the inliers.
LineMotionFit fit_line_motion(const LineSegment& line, const std::vector<Eigen::Vector2d>& before,
                              const std::vector<Eigen::Vector2d>& after, const LineMotionFitConfig& config);

}  // namespace pllvo::lines
