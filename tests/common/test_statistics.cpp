#include <gtest/gtest.h>

#include "pllvo/common/statistics.h"

namespace pllvo {
namespace {

TEST(Statistics, MedianIsTheMiddleValueAndTheUpperOneOfAnEvenCount) {
  EXPECT_DOUBLE_EQ(median({7.0, -1.0, 3.0}), 3.0);
  EXPECT_DOUBLE_EQ(median({4.0, 1.0, 9.0, 2.0}), 4.0);
  EXPECT_DOUBLE_EQ(median({5.5}), 5.5);
  EXPECT_DOUBLE_EQ(median({}), 0.0);
}

}  // namespace
}  // namespace pllvo
