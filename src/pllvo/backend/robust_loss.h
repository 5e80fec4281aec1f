#pragma once
// Robust losses on squared residual norms s (pixels^2), with the same definitions as
// Ceres' HuberLoss / CauchyLoss so that the hand-written pose refiner and the Ceres bundle
// adjustment minimise the same costs.
#include <memory>
#include <string>

#include <ceres/loss_function.h>

#include "pllvo/common/yaml_config.h"

namespace pllvo::backend {

enum class LossType { kNone, kHuber, kCauchy };

struct RobustLoss {
  LossType type = LossType::kHuber;
  double scale_px = 2.0;  ///< residual norm (pixels) where the loss leaves the quadratic

  /// rho(s): Huber s for s <= a^2, else 2 a sqrt(s) - a^2; Cauchy a^2 log(1 + s / a^2).
  double rho(double s) const;
  /// rho'(s): the weight of a residual in iteratively reweighted least squares.
  double weight(double s) const;
  /// A new Ceres loss with the same definition (nullptr for kNone); the caller owns it.
  ceres::LossFunction* make_ceres() const;

  /// Reads `<prefix>loss` (none | huber | cauchy) and `<prefix>loss_scale_px`.
  void load(const ConfigNode& node, const std::string& prefix);
};

std::string to_string(LossType type);

}  // namespace pllvo::backend
