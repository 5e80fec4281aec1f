#include <gtest/gtest.h>

#include "pllvo/eval/alignment.h"
#include "pllvo/eval/eval_error.h"

using namespace pllvo::eval;

namespace {

PoseList random_path(int n) {
  PoseList poses;
  for (int i = 0; i < n; ++i) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(0.1 * i, Eigen::Vector3d(0.2, 1, 0.3).normalized()).toRotationMatrix();
    T.translation() = Eigen::Vector3d(std::sin(0.3 * i) * 4, std::cos(0.2 * i) * 3, 0.1 * i);
    poses.push_back(T);
  }
  return poses;
}

/// est = S^-1 * ref with a known similarity S (positions: p_est = (R^T (p_ref - t)) / s).
PoseList transformed(const PoseList& ref, const Similarity& S) {
  PoseList est;
  for (const auto& T : ref) {
    Eigen::Isometry3d E = Eigen::Isometry3d::Identity();
    E.linear() = S.rotation.transpose() * T.linear();
    E.translation() = S.rotation.transpose() * (T.translation() - S.translation) / S.scale;
    est.push_back(E);
  }
  return est;
}

Similarity known() {
  Similarity S;
  S.rotation = Eigen::AngleAxisd(2.0, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
  S.translation = Eigen::Vector3d(3, -1, 7);
  S.scale = 2.5;
  return S;
}

}  // namespace

TEST(Alignment, Sim3RecoversAKnownSimilarityAndAppliesIt) {
  const auto ref = random_path(30);
  const auto S = known();
  auto est = transformed(ref, S);
  const auto a = align(est, ref, AlignMode::sim3);
  EXPECT_EQ(a.n_used, 30u);
  EXPECT_LT((a.transform.rotation - S.rotation).norm(), 1e-12);
  EXPECT_LT((a.transform.translation - S.translation).norm(), 1e-11);
  EXPECT_NEAR(a.transform.scale, S.scale, 1e-12);
  for (size_t i = 0; i < ref.size(); ++i) EXPECT_LT((est[i].matrix() - ref[i].matrix()).norm(), 1e-11);
}

TEST(Alignment, Se3KeepsScaleAndScaleOnlyKeepsRotation) {
  const auto ref = random_path(30);
  auto S = known();
  S.scale = 1.0;
  auto est = transformed(ref, S);
  const auto a = align(est, ref, AlignMode::se3, 5);  // 5 exact poses are enough
  EXPECT_EQ(a.n_used, 5u);
  EXPECT_EQ(a.transform.scale, 1.0);
  for (size_t i = 0; i < ref.size(); ++i) EXPECT_LT((est[i].matrix() - ref[i].matrix()).norm(), 1e-11);

  auto scaled = ref;
  for (auto& T : scaled) T.translation() *= 0.5;
  const auto before = scaled;
  const auto b = align(scaled, ref, AlignMode::scale_only);
  EXPECT_NEAR(b.transform.scale, 2.0, 1e-12);
  for (size_t i = 0; i < ref.size(); ++i) {
    EXPECT_EQ(scaled[i].linear(), before[i].linear());  // scale only: rotations untouched
    EXPECT_LT((scaled[i].translation() - 2.0 * before[i].translation()).norm(), 1e-15);
  }
}

TEST(Alignment, CollinearPointsAreDegeneratePlanarAreNot) {
  PoseList line, plane;
  for (int i = 0; i < 5; ++i) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = Eigen::Vector3d(i, 0, 0);
    line.push_back(T);
    T.translation() = Eigen::Vector3d(i, i * i, 0);
    plane.push_back(T);
  }
  auto est = line;
  try {
    align(est, line, AlignMode::se3);
    ADD_FAILURE() << "collinear points aligned";
  } catch (const EvalError& e) {
    EXPECT_EQ(e.kind(), EvalErrorKind::geometry);
    EXPECT_EQ(std::string(e.what()), "Degenerate covariance rank, Umeyama alignment is not possible");
  }
  est = plane;  // rank 2: the reflection check fixes the third axis, as in evo
  const auto a = align(est, plane, AlignMode::sim3);
  EXPECT_LT((a.transform.rotation - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  EXPECT_NEAR(a.transform.scale, 1.0, 1e-12);
}

TEST(Alignment, CollinearReferenceIsAlignedWhenAllowed) {
  // A slider: the reference moves along x only. The estimate is the same line, noisy off it,
  // rotated, scaled by 1/3 and shifted; the allowed fit must undo the scale and bring the error
  // down to the noise, and no rotation may do better (checked against random rotations).
  PoseList ref, est;
  Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.3, -1, 0.5).normalized()).toRotationMatrix();
  for (int i = 0; i < 30; ++i) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = Eigen::Vector3d(0.1 + 0.03 * i, 0, 0);
    ref.push_back(T);
    const Eigen::Vector3d noise(0.002 * std::sin(1.3 * i), 0.003 * std::cos(0.7 * i), 0.002 * std::sin(2.1 * i));
    T.translation() = R * (T.translation() + noise) / 3.0 + Eigen::Vector3d(1, 2, 3);
    est.push_back(T);
  }
  auto refused = est;
  EXPECT_THROW(align(refused, ref, AlignMode::sim3), EvalError);
  auto aligned = est;
  const auto a = align(aligned, ref, AlignMode::sim3, -1, true);
  EXPECT_NEAR(a.transform.scale, 3.0, 0.02);
  auto rmse = [&](const PoseList& e) {
    double sum = 0;
    for (size_t i = 0; i < ref.size(); ++i) sum += (e[i].translation() - ref[i].translation()).squaredNorm();
    return std::sqrt(sum / ref.size());
  };
  const double best = rmse(aligned);
  EXPECT_LT(best, 0.004);
  for (int k = 0; k < 50; ++k) {  // other rotations mapping the line onto itself, same scale and centre
    auto other = est;
    const Eigen::Matrix3d Q = a.transform.rotation *
        Eigen::AngleAxisd(0.1 * (k + 1), a.transform.rotation.transpose() * Eigen::Vector3d::UnitX()).toRotationMatrix();
    for (auto& T : other) T.translation() = a.transform.scale * Q * T.translation() + a.transform.translation;
    EXPECT_GE(rmse(other), best - 1e-12);
  }
}

TEST(Alignment, OriginAlignmentMovesTheFirstPoseOntoTheReference) {
  const auto ref = random_path(10);
  auto S = known();
  S.scale = 1.0;
  auto est = transformed(ref, S);
  const Eigen::Isometry3d T = align_origin(est, ref);
  EXPECT_LT((T.linear() - S.rotation).norm(), 1e-12);
  for (size_t i = 0; i < ref.size(); ++i) EXPECT_LT((est[i].matrix() - ref[i].matrix()).norm(), 1e-11);
}
