#include "pllvo/backend/robust_loss.h"

#include <cmath>

#include "pllvo/geometry/config_choice.h"

namespace pllvo::backend {

namespace {
const geometry::Choices<LossType> kLossChoices = {
    {"none", LossType::kNone}, {"huber", LossType::kHuber}, {"cauchy", LossType::kCauchy}};
}

double RobustLoss::rho(double s) const {
  const double a2 = scale_px * scale_px;
  switch (type) {
    case LossType::kNone: return s;
    case LossType::kHuber: return s <= a2 ? s : 2.0 * scale_px * std::sqrt(s) - a2;
    case LossType::kCauchy: return a2 * std::log1p(s / a2);
  }
  return s;
}

double RobustLoss::weight(double s) const {
  const double a2 = scale_px * scale_px;
  switch (type) {
    case LossType::kNone: return 1.0;
    case LossType::kHuber: return s <= a2 ? 1.0 : scale_px / std::sqrt(s);
    case LossType::kCauchy: return 1.0 / (1.0 + s / a2);
  }
  return 1.0;
}

ceres::LossFunction* RobustLoss::make_ceres() const {
  switch (type) {
    case LossType::kNone: return nullptr;
    case LossType::kHuber: return new ceres::HuberLoss(scale_px);
    case LossType::kCauchy: return new ceres::CauchyLoss(scale_px);
  }
  return nullptr;
}

void RobustLoss::load(const ConfigNode& node, const std::string& prefix) {
  geometry::get_choice(node, prefix + "loss", type, kLossChoices);
  node.get(prefix + "loss_scale_px", scale_px);
  if (!(scale_px > 0)) throw InputError(node.file(), node.path(prefix + "loss_scale_px"), "must be positive");
}

std::string to_string(LossType type) { return geometry::choice_name(type, kLossChoices); }

}  // namespace pllvo::backend
