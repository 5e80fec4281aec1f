#include <gtest/gtest.h>

#include "pllvo/geometry/pose.h"

using namespace pllvo::geometry;

TEST(Pose, NearestRotationSnapsANoisyFrameAndSolvesWahba) {
  const Eigen::Matrix3d R = so3_exp(Eigen::Vector3d(0.3, -0.2, 0.5));
  Eigen::Matrix3d noisy = R;
  noisy(0, 1) += 1e-3;
  noisy(2, 0) -= 2e-3;
  const Eigen::Matrix3d snapped = nearest_rotation(noisy);
  EXPECT_LT((snapped * snapped.transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  EXPECT_NEAR(snapped.determinant(), 1.0, 1e-12);
  EXPECT_LT(rotation_angle(snapped.transpose() * R), 2e-3);
  // Wahba: the sum of b a^T over pairs b = R a gives R back.
  Eigen::Matrix3d B = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d a : {Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0.2, 1, 0), Eigen::Vector3d(0, 0.3, 1)})
    B += (R * a) * a.transpose();
  EXPECT_LT(rotation_angle(nearest_rotation(B).transpose() * R), 1e-9);
  // A reflection is not a rotation: the nearest proper one flips the weakest axis.
  const Eigen::Matrix3d mirror = Eigen::Vector3d(1, 1, -0.5).asDiagonal();
  EXPECT_NEAR(nearest_rotation(mirror).determinant(), 1.0, 1e-12);
}
