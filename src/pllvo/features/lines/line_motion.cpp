#include "pllvo/features/lines/line_motion.h"

#include <cmath>

#include <Eigen/LU>

namespace pllvo::lines {

LineSegment LineMotion::apply(const LineSegment& s) const {
  LineSegment out = s;
  out.start = apply(s.start, s.start);
  out.end = apply(s.end, s.start);
  return out;
}

void LineMotionFitConfig::load(const ConfigNode& node) {
  node.get("huber_normal_px", huber_normal_px);
  node.get("huber_tangential_px", huber_tangential_px);
  node.get("irls_iterations", irls_iterations);
  node.get("inlier_normal_px", inlier_normal_px);
  node.get("inlier_tangential_px", inlier_tangential_px);
  node.reject_unknown_keys();
  if (huber_normal_px <= 0.0 || huber_tangential_px <= 0.0)
    throw InputError(node.file(), node.path("huber_normal_px"), "Huber scales must be > 0");
  if (irls_iterations < 0) throw InputError(node.file(), node.path("irls_iterations"), "must be >= 0");
}

namespace {
double huber_weight(double r, double k) {
  const double a = std::abs(r);
  return a <= k ? 1.0 : k / a;
}

struct Sample {
  Eigen::Vector2d p, d;  // position in frame k, displacement to frame k+1
};

// Weighted normal equations of eq. 6; per-sample weights across (wn) and along (wt) the line.
bool solve(const std::vector<Sample>& s, const std::vector<double>& wn, const std::vector<double>& wt,
           const Eigen::Vector2d& anchor, const Eigen::Vector2d& n, const Eigen::Vector2d& t, LineMotion& m) {
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  const Eigen::Matrix2d Pn = n * n.transpose(), Pt = t * t.transpose();
  for (size_t i = 0; i < s.size(); ++i) {
    if (wn[i] <= 0.0 && wt[i] <= 0.0) continue;
    Eigen::Matrix<double, 2, 3> J;
    J << 1.0, 0.0, -(s[i].p.y() - anchor.y()), 0.0, 1.0, s[i].p.x() - anchor.x();
    const Eigen::Matrix2d W = wn[i] * Pn + wt[i] * Pt;
    A += J.transpose() * W * J;
    b += J.transpose() * W * s[i].d;
  }
  // Singular when fewer than two distinct samples carry weight.
  Eigen::Matrix3d inv;
  double det = 0.0;
  bool invertible = false;
  A.computeInverseAndDetWithCheck(inv, det, invertible, 1e-12 * std::max(1.0, std::pow(A.diagonal().maxCoeff(), 3)));
  if (!invertible) return false;
  const Eigen::Vector3d g = inv * b;
  if (!g.allFinite()) return false;
  m = {g(0), g(1), g(2)};
  return true;
}
}  // namespace

LineMotionFit fit_line_motion(const LineSegment& line, const std::vector<Eigen::Vector2d>& before,
                              const std::vector<Eigen::Vector2d>& after, const LineMotionFitConfig& config) {
  LineMotionFit fit;
  const size_t N = std::min(before.size(), after.size());
  fit.inlier.assign(N, 0);
  if (N < 2) return fit;
  std::vector<Sample> s(N);
  for (size_t i = 0; i < N; ++i) s[i] = {before[i], after[i] - before[i]};
  const Eigen::Vector2d anchor = line.start, t = line.direction(), n = line.normal();
  const double sn2 = config.huber_normal_px * config.huber_normal_px;
  const double st2 = config.huber_tangential_px * config.huber_tangential_px;

  // Weights are Huber weights divided by the squared scale (normalised residuals).
  std::vector<double> wn(N, 1.0 / sn2), wt(N, 1.0 / st2);
  LineMotion m;
  if (!solve(s, wn, wt, anchor, n, t, m)) return fit;
  auto residual = [&](size_t i, const LineMotion& mm) -> Eigen::Vector2d {
    return mm.apply(s[i].p, anchor) - (s[i].p + s[i].d);
  };
  for (int it = 0; it < config.irls_iterations; ++it) {
    bool all_inside = true;  // every residual within its Huber scale: the LS solution is final
    for (size_t i = 0; i < N; ++i) {
      const Eigen::Vector2d r = residual(i, m);
      wn[i] = huber_weight(n.dot(r), config.huber_normal_px) / sn2;
      wt[i] = huber_weight(t.dot(r), config.huber_tangential_px) / st2;
      all_inside = all_inside && wn[i] * sn2 >= 1.0 && wt[i] * st2 >= 1.0;
    }
    if (all_inside) break;
    const LineMotion previous = m;
    if (!solve(s, wn, wt, anchor, n, t, m)) return fit;
    if (std::abs(m.g1 - previous.g1) + std::abs(m.g2 - previous.g2) + std::abs(m.g3 - previous.g3) * 100.0 < 1e-5) break;
  }

  // Inliers, then a least-squares refit on them alone.
  auto classify = [&](const LineMotion& mm) {
    fit.inliers = 0;
    for (size_t i = 0; i < N; ++i) {
      const Eigen::Vector2d r = residual(i, mm);
      fit.inlier[i] = std::abs(n.dot(r)) <= config.inlier_normal_px && std::abs(t.dot(r)) <= config.inlier_tangential_px;
      fit.inliers += fit.inlier[i];
    }
  };
  classify(m);
  if (fit.inliers < 2) return fit;
  for (size_t i = 0; i < N; ++i) {
    wn[i] = fit.inlier[i] ? 1.0 / sn2 : 0.0;
    wt[i] = fit.inlier[i] ? 1.0 / st2 : 0.0;
  }
  if (!solve(s, wn, wt, anchor, n, t, m)) return fit;
  classify(m);
  if (fit.inliers < 2) return fit;

  // Residual and stretch over the inliers.
  const LineSegment moved = m.apply(line);
  const Eigen::Vector2d t2 = moved.direction();
  double ss = 0.0, sa = 0.0, sb = 0.0, saa = 0.0, sab = 0.0;
  for (size_t i = 0; i < N; ++i) {
    if (!fit.inlier[i]) continue;
    ss += std::pow(n.dot(residual(i, m)), 2);
    const double a = t.dot(s[i].p - line.start);
    const double b = t2.dot(s[i].p + s[i].d - moved.start);
    sa += a, sb += b, saa += a * a, sab += a * b;
  }
  const double k = fit.inliers;
  const double var = saa - sa * sa / k;
  if (var <= 1e-9) return fit;  // all inliers at one spot: no line left
  fit.stretch = (sab - sa * sb / k) / var;
  fit.rms_normal_px = std::sqrt(ss / k);
  fit.motion = m;
  fit.valid = true;
  return fit;
}

}  // namespace pllvo::lines
