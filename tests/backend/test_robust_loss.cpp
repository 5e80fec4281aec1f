#include <gtest/gtest.h>

#include <memory>

#include "pllvo/backend/robust_loss.h"

using namespace pllvo::backend;

TEST(RobustLoss, MatchesCeresDefinitions) {
  for (const LossType type : {LossType::kHuber, LossType::kCauchy}) {
    const RobustLoss loss{type, 2.0};
    const std::unique_ptr<ceres::LossFunction> ceres_loss(loss.make_ceres());
    ASSERT_NE(ceres_loss, nullptr);
    for (double s : {0.0, 0.5, 3.9, 4.0, 4.1, 25.0, 1e4}) {
      double rho[3];
      ceres_loss->Evaluate(s, rho);
      EXPECT_NEAR(loss.rho(s), rho[0], 1e-12 * (1 + rho[0])) << to_string(type) << " s=" << s;
      EXPECT_NEAR(loss.weight(s), rho[1], 1e-12) << to_string(type) << " s=" << s;
    }
  }
  const RobustLoss none{LossType::kNone, 2.0};
  EXPECT_EQ(none.make_ceres(), nullptr);
  EXPECT_EQ(none.rho(7.0), 7.0);
  EXPECT_EQ(none.weight(7.0), 1.0);
}

TEST(RobustLoss, HuberIsQuadraticInsideAndLinearOutside) {
  const RobustLoss huber{LossType::kHuber, 2.0};
  EXPECT_EQ(huber.rho(3.0), 3.0);
  EXPECT_EQ(huber.weight(3.0), 1.0);
  // |r| = 10 px: rho = 2 * 2 * 10 - 4, weight = 2 / 10.
  EXPECT_NEAR(huber.rho(100.0), 36.0, 1e-12);
  EXPECT_NEAR(huber.weight(100.0), 0.2, 1e-12);
  // Cauchy weighs a 10 px residual far less than Huber.
  EXPECT_LT(RobustLoss({LossType::kCauchy, 2.0}).weight(100.0), 0.05);
}
