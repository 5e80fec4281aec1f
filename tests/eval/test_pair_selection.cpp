#include <gtest/gtest.h>

#include <numbers>

#include "pllvo/common/error.h"
#include "pllvo/eval/eval_error.h"
#include "pllvo/eval/pair_selection.h"

using namespace pllvo::eval;

namespace {

/// Poses along x with the given step lengths, rotating about z by `deg_per_step`.
PoseList path(const std::vector<double>& steps, double deg_per_step = 0.0) {
  PoseList poses;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  poses.push_back(T);
  for (size_t i = 0; i < steps.size(); ++i) {
    T.translation().x() += steps[i];
    T.linear() = Eigen::AngleAxisd((i + 1) * deg_per_step * std::numbers::pi / 180, Eigen::Vector3d::UnitZ())
                     .toRotationMatrix();
    poses.push_back(T);
  }
  return poses;
}

}  // namespace

TEST(PairSelection, Frames) {
  const auto poses = path(std::vector<double>(9, 1.0));  // 10 poses
  EXPECT_EQ(select_pairs(poses, {3, DeltaUnit::frames}), (IdPairs{{0, 3}, {3, 6}, {6, 9}}));
  PairOptions all{4, DeltaUnit::frames};
  all.all_pairs = true;
  EXPECT_EQ(select_pairs(poses, all), (IdPairs{{0, 4}, {1, 5}, {2, 6}, {3, 7}, {4, 8}, {5, 9}}));
}

TEST(PairSelection, MetresConsecutiveStartWhereThePathFirstReachesDelta) {
  // Path lengths: 0.5, 1.0 | 1.5, 2.0 | 2.5, 3.0 |: the first id is 2, not 0.
  const auto poses = path({0.5, 0.5, 0.5, 0.5, 0.5, 0.5});
  EXPECT_EQ(select_pairs(poses, {1.0, DeltaUnit::meters}), (IdPairs{{2, 4}, {4, 6}}));
}

TEST(PairSelection, MetresAllPairsNearestWithinTolerance) {
  const auto poses = path({0.5, 0.5, 0.25, 0.8, 0.5});  // D = 0, .5, 1, 1.25, 2.05, 2.55
  PairOptions o{1.0, DeltaUnit::meters, 0.1, true};
  // i=0: D=1 (j=2); i=1: |0.75-1|,|1.55-1| -> none; i=2: 1.05 (j=4); i=3: 1.3 -> none; i=4: .5 -> none
  EXPECT_EQ(select_pairs(poses, o), (IdPairs{{0, 2}, {2, 4}}));
}

TEST(PairSelection, AnglesConsecutiveAndAllPairs) {
  const auto poses = path(std::vector<double>(8, 0.1), 4.0);  // 4 deg per step
  EXPECT_EQ(select_pairs(poses, {10.0, DeltaUnit::degrees}), (IdPairs{{0, 3}, {3, 6}}));
  PairOptions all{0.1396263, DeltaUnit::radians, 0.01, true};  // 8 deg +- 1 %
  EXPECT_EQ(select_pairs(poses, all), (IdPairs{{0, 2}, {1, 3}, {2, 4}, {3, 5}, {4, 6}, {5, 7}, {6, 8}}));
}

TEST(PairSelection, EmptyListIsFilterErrorAndBadDeltaIsInputError) {
  const auto poses = path({1.0, 1.0});
  try {
    select_pairs(poses, {10, DeltaUnit::frames});
    ADD_FAILURE() << "no error";
  } catch (const EvalError& e) {
    EXPECT_EQ(e.kind(), EvalErrorKind::filter);
    EXPECT_EQ(std::string(e.what()),
              "delta = 10 (frames) produced an empty index list - try lower values or a less strict tolerance");
  }
  EXPECT_THROW(select_pairs(poses, {0.0, DeltaUnit::meters}), pllvo::InputError);
  EXPECT_THROW(select_pairs(poses, {1.5, DeltaUnit::frames}), pllvo::InputError);
  EXPECT_EQ(parse_delta_unit("m"), DeltaUnit::meters);
  EXPECT_EQ(parse_delta_unit("deg"), DeltaUnit::degrees);
  EXPECT_THROW(parse_delta_unit("km"), pllvo::InputError);
}
