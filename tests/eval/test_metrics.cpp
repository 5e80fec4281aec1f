#include <gtest/gtest.h>

#include <numbers>

#include "pllvo/common/error.h"
#include "pllvo/eval/eval_error.h"
#include "pllvo/eval/metrics.h"

using namespace pllvo::eval;

namespace {
Eigen::Isometry3d pose(double yaw_deg, const Eigen::Vector3d& t) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(yaw_deg * std::numbers::pi / 180, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = t;
  return T;
}
}  // namespace

TEST(Metrics, ApeRelations) {
  const PoseList ref{pose(0, {0, 0, 0}), pose(90, {1, 0, 0})};
  const PoseList est{pose(0, {0, 3, 4}), pose(100, {1, 0, 0})};
  EXPECT_EQ(ape_errors(ref, est, PoseRelation::trans_part), (std::vector<double>{5.0, 0.0}));
  const auto deg = ape_errors(ref, est, PoseRelation::angle_deg);
  EXPECT_NEAR(deg[0], 0.0, 1e-12);
  EXPECT_NEAR(deg[1], 10.0, 1e-12);
  // rot_part is the Frobenius norm 2 sqrt(2) sin(theta / 2), not an angle.
  EXPECT_NEAR(ape_errors(ref, est, PoseRelation::rot_part)[1], 2 * std::sqrt(2.0) * std::sin(5 * std::numbers::pi / 180),
              1e-12);
  EXPECT_NEAR(ape_errors(ref, est, PoseRelation::full)[0], 5.0, 1e-12);
  EXPECT_THROW(ape_errors(ref, est, PoseRelation::point_distance_error_ratio), EvalError);
}

TEST(Metrics, AngleAbove180FoldsBack) {
  const PoseList ref{pose(0, {0, 0, 0})};
  const PoseList est{pose(200, {0, 0, 0})};
  EXPECT_NEAR(ape_errors(ref, est, PoseRelation::angle_deg)[0], 160.0, 1e-9);
  EXPECT_NEAR(ape_errors(ref, est, PoseRelation::angle_rad)[0], 160.0 * std::numbers::pi / 180, 1e-12);
}

TEST(Metrics, RpeIsInvariantToAGlobalTransformAndRatioSkipsZeroDistances) {
  const PoseList ref{pose(0, {0, 0, 0}), pose(30, {2, 0, 0}), pose(60, {2, 0, 0})};
  PoseList est;
  const Eigen::Isometry3d G = pose(45, {5, -3, 1});
  for (const auto& T : ref) est.push_back(G * T);
  est[2].translation() += Eigen::Vector3d(0, 0, 1);  // error only on the second pair
  const IdPairs pairs{{0, 1}, {1, 2}};
  const auto trans = rpe_errors(ref, est, pairs, PoseRelation::trans_part);
  EXPECT_NEAR(trans[0], 0.0, 1e-12);
  EXPECT_NEAR(trans[1], 1.0, 1e-12);
  const auto ratio = rpe_errors(ref, est, pairs, PoseRelation::point_distance_error_ratio);
  ASSERT_EQ(ratio.size(), 1u);  // the second reference pair has zero distance
  EXPECT_NEAR(ratio[0], 0.0, 1e-12);
  EXPECT_NEAR(rpe_errors(ref, est, pairs, PoseRelation::point_distance)[1], 1.0, 1e-12);
}

TEST(Metrics, RelationNames) {
  for (const char* name : {"trans_part", "rot_part", "full", "angle_deg", "angle_rad", "point_distance",
                           "point_distance_error_ratio"})
    EXPECT_EQ(pose_relation_name(parse_pose_relation(name)), name);
  EXPECT_EQ(unit_name(PoseRelation::rot_part), "unit-less");
  EXPECT_EQ(unit_name(PoseRelation::point_distance_error_ratio), "%");
  EXPECT_THROW(parse_pose_relation("angle"), pllvo::InputError);
}
