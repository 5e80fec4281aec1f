#include <gtest/gtest.h>

#include <cmath>

#include "pllvo/common/error.h"
#include "pllvo/eval/statistics.h"

using namespace pllvo::eval;

TEST(Statistics, EvenCountPopulationStd) {
  const auto s = compute_statistics({4.0, 1.0, 3.0, 2.0});
  EXPECT_DOUBLE_EQ(s.mean, 2.5);
  EXPECT_DOUBLE_EQ(s.median, 2.5);                 // mean of the two middle values
  EXPECT_DOUBLE_EQ(s.std, std::sqrt(1.25));        // ddof = 0
  EXPECT_DOUBLE_EQ(s.sse, 30.0);
  EXPECT_DOUBLE_EQ(s.rmse, std::sqrt(7.5));
  EXPECT_DOUBLE_EQ(s.min, 1.0);
  EXPECT_DOUBLE_EQ(s.max, 4.0);
}

TEST(Statistics, OddCountAndEmpty) {
  const auto s = compute_statistics({5.0, 0.5, 2.0});
  EXPECT_DOUBLE_EQ(s.median, 2.0);
  EXPECT_DOUBLE_EQ(s.mean, 2.5);
  EXPECT_THROW(compute_statistics({}), pllvo::InternalError);
}
