#include <gtest/gtest.h>

#include <cstdio>

#include "../support/synthetic_scene.h"
#include "pllvo/backend/pose_refiner.h"

using namespace pllvo::backend;
using namespace pllvo::test;

namespace {
/// Observations of the scene's landmarks by camera `cam` (points with `sigma_px` noise, lines
/// from noisy endpoints); the first `outlier_fraction` of the points and lines get wrong
/// observations (a random offset of 15-40 px).
PoseRefinementProblem make_problem(const SyntheticScene& scene, int cam, double sigma_px, double outlier_fraction,
                                   std::mt19937& rng) {
  PoseRefinementProblem p;
  p.focal_px = kFocal;
  const Pose& T = scene.T_world_cam[cam];
  std::uniform_real_distribution<double> angle(0, 2 * M_PI), offset(15, 40);
  const int point_outliers = static_cast<int>(outlier_fraction * scene.points.size());
  const int line_outliers = static_cast<int>(outlier_fraction * scene.lines.size());
  for (size_t i = 0; i < scene.points.size(); ++i) {
    Eigen::Vector2d xy;
    observe(T, scene.points[i], xy);
    xy = add_noise(xy, sigma_px, rng);
    if (static_cast<int>(i) < point_outliers) {
      const double a = angle(rng);
      xy += offset(rng) / kFocal * Eigen::Vector2d(std::cos(a), std::sin(a));
    }
    p.points.push_back({scene.points[i], xy, 0});
  }
  for (size_t i = 0; i < scene.lines.size(); ++i) {
    Eigen::Vector3d l = observe_line(T, scene.lines[i], sigma_px, rng);
    if (static_cast<int>(i) < line_outliers) l.z() += (angle(rng) < M_PI ? 1 : -1) * offset(rng) / kFocal;
    p.lines.push_back({scene.lines[i].start, scene.lines[i].end, l, 0});
  }
  return p;
}

Pose perturb(const Pose& T, double translation, double rotation_deg, std::mt19937& rng) {
  std::normal_distribution<double> n(0, 1);
  const Eigen::Vector3d dt = Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized() * translation;
  const Eigen::Vector3d axis = Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
  return pllvo::geometry::make_pose(T.linear() * Eigen::AngleAxisd(rotation_deg * M_PI / 180, axis).toRotationMatrix(),
                                    T.translation() + dt);
}
}  // namespace

TEST(PoseRefiner, ConvergesFromAPerturbedPoseWithNoiseFreeData) {
  const auto scene = make_scene(4, 100, 20, 70);
  std::mt19937 rng(71);
  const PoseRefiner refiner;
  for (int cam = 0; cam < 4; ++cam) {
    auto problem = make_problem(scene, cam, 0.0, 0.0, rng);
    problem.T_world_cam = perturb(scene.T_world_cam[cam], 0.15, 5.0, rng);
    const auto r = refiner.refine(problem);
    ASSERT_TRUE(r.ok);
    EXPECT_LT(translation_error(r.T_world_cam, scene.T_world_cam[cam]), 1e-3);
    EXPECT_LT(rotation_error_deg(r.T_world_cam, scene.T_world_cam[cam]), 0.05);
    EXPECT_EQ(r.num_point_inliers, 100);
    EXPECT_EQ(r.num_line_inliers, 20);
    EXPECT_GT(r.initial_rms_px, 10.0);
    EXPECT_LT(r.final_rms_px, 1e-6);
    std::printf("[ pose refinement ] camera %d: %.2e m, %.2e deg after %d iterations\n", cam,
                translation_error(r.T_world_cam, scene.T_world_cam[cam]),
                rotation_error_deg(r.T_world_cam, scene.T_world_cam[cam]), r.iterations);
  }
}

TEST(PoseRefiner, LinesAloneDetermineThePose) {
  const auto scene = make_scene(2, 0, 30, 72);
  std::mt19937 rng(73);
  auto problem = make_problem(scene, 1, 0.0, 0.0, rng);
  problem.T_world_cam = perturb(scene.T_world_cam[1], 0.1, 3.0, rng);
  const auto r = PoseRefiner().refine(problem);
  ASSERT_TRUE(r.ok);
  EXPECT_LT(translation_error(r.T_world_cam, scene.T_world_cam[1]), 1e-3);
  EXPECT_LT(rotation_error_deg(r.T_world_cam, scene.T_world_cam[1]), 0.05);
}

TEST(PoseRefiner, DownWeightsAndFlagsOutliers) {
  // 0.7 px noise, 30% of points and lines observed 15-40 px off.
  const auto scene = make_scene(1, 150, 30, 74);
  std::mt19937 rng(75);
  auto problem = make_problem(scene, 0, 0.7, 0.3, rng);
  problem.T_world_cam = perturb(scene.T_world_cam[0], 0.05, 2.0, rng);

  const auto robust = PoseRefiner().refine(problem);
  ASSERT_TRUE(robust.ok);
  const double t_err = translation_error(robust.T_world_cam, scene.T_world_cam[0]);
  const double r_err = rotation_error_deg(robust.T_world_cam, scene.T_world_cam[0]);
  EXPECT_LT(t_err, 0.02);
  EXPECT_LT(r_err, 0.1);
  // The first 45 points and 9 lines are the outliers.
  int point_outliers_kept = 0, point_inliers_lost = 0, line_outliers_kept = 0, line_inliers_lost = 0;
  for (int i = 0; i < 150; ++i) {
    if (i < 45 && robust.point_inliers[i]) ++point_outliers_kept;
    if (i >= 45 && !robust.point_inliers[i]) ++point_inliers_lost;
  }
  for (int i = 0; i < 30; ++i) {
    if (i < 9 && robust.line_inliers[i]) ++line_outliers_kept;
    if (i >= 9 && !robust.line_inliers[i]) ++line_inliers_lost;
  }
  EXPECT_EQ(point_outliers_kept, 0);
  EXPECT_EQ(line_outliers_kept, 0);
  EXPECT_LE(point_inliers_lost, 3);
  EXPECT_LE(line_inliers_lost, 1);

  // The same problem without a robust loss and without outlier rounds ends up further away.
  PoseRefinerConfig plain;
  plain.point_loss.type = plain.line_loss.type = LossType::kNone;
  plain.rounds = 1;
  const auto naive = PoseRefiner(plain).refine(problem);
  EXPECT_GT(translation_error(naive.T_world_cam, scene.T_world_cam[0]), 3 * t_err);
  std::printf("[ pose refinement, 30%% outliers ] robust: %.4f m %.4f deg; least squares: %.4f m %.4f deg\n", t_err,
              r_err, translation_error(naive.T_world_cam, scene.T_world_cam[0]),
              rotation_error_deg(naive.T_world_cam, scene.T_world_cam[0]));
}

TEST(PoseRefiner, MotionPriorWeighsAgainstTheObservations) {
  // Three points do not pin a pose well under noise; the prior decides how far it may move.
  const auto scene = make_scene(1, 6, 0, 76);
  std::mt19937 rng(77);
  auto problem = make_problem(scene, 0, 0.0, 0.0, rng);
  const Pose truth = scene.T_world_cam[0];
  Pose predicted = truth;
  predicted.translation() += Eigen::Vector3d(0.05, 0, 0);
  problem.T_world_cam = predicted;
  problem.predicted_T_world_cam = predicted;

  PoseRefinerConfig config;
  config.min_inliers = 3;
  config.prior_sigma_position = 1e-4;  // trust the prediction
  config.prior_sigma_rotation_deg = 1e-3;
  auto r = PoseRefiner(config).refine(problem);
  EXPECT_LT(translation_error(r.T_world_cam, predicted), 2e-3);

  config.prior_sigma_position = 10;  // trust the observations
  config.prior_sigma_rotation_deg = 100;
  r = PoseRefiner(config).refine(problem);
  EXPECT_LT(translation_error(r.T_world_cam, truth), 1e-4);

  config.use_motion_prior = false;  // the switch turns the prior off altogether
  config.prior_sigma_position = 1e-4;
  r = PoseRefiner(config).refine(problem);
  EXPECT_LT(translation_error(r.T_world_cam, truth), 1e-4);
}

TEST(PoseRefiner, StereoRigObservations) {
  const auto scene = make_scene(2, 60, 10, 78);
  std::mt19937 rng(79);
  const Pose T_right_left = pllvo::geometry::make_pose(Eigen::Matrix3d::Identity(), Eigen::Vector3d(-0.11, 0, 0));
  PoseRefinementProblem problem;
  problem.focal_px = kFocal;
  problem.T_cam_cam0 = {Pose::Identity(), T_right_left};
  const Pose T_left = scene.T_world_cam[1], T_right = T_left * T_right_left.inverse();
  for (const auto& p : scene.points) {
    Eigen::Vector2d l, r;
    observe(T_left, p, l);
    observe(T_right, p, r);
    problem.points.push_back({p, l, 0});
    problem.points.push_back({p, r, 1});
  }
  for (const auto& s : scene.lines) problem.lines.push_back({s.start, s.end, observe_line(T_right, s, 0.0, rng), 1});
  problem.T_world_cam = perturb(T_left, 0.1, 3.0, rng);
  const auto r = PoseRefiner().refine(problem);
  ASSERT_TRUE(r.ok);
  EXPECT_LT(translation_error(r.T_world_cam, T_left), 1e-3);
  EXPECT_LT(rotation_error_deg(r.T_world_cam, T_left), 0.05);

  problem.points[0].camera = 2;  // no such camera
  EXPECT_THROW(PoseRefiner().refine(problem), pllvo::InternalError);
}

TEST(PoseRefiner, TooFewInliersIsNotOk) {
  const auto scene = make_scene(1, 5, 0, 80);
  std::mt19937 rng(81);
  auto problem = make_problem(scene, 0, 0.0, 0.0, rng);
  problem.T_world_cam = scene.T_world_cam[0];
  const auto r = PoseRefiner().refine(problem);  // default min_inliers = 10
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.num_point_inliers, 5);
  EXPECT_FALSE(PoseRefiner().refine(PoseRefinementProblem{}).ok);
}

TEST(PoseRefiner, DownWeightedPointsPullThePoseLess) {
  // A fifth of the map points sit at 70 % of their depth from the camera (a short-baseline
  // triangulation), a pull of a few pixels each, below the outlier threshold; weighted at 0.05
  // they move the pose a small fraction of what they move it at full weight.
  const auto scene = make_scene(2, 100, 0, 72);
  std::mt19937 rng(73);
  auto problem = make_problem(scene, 1, 0.0, 0.0, rng);
  const Eigen::Vector3d centre = scene.T_world_cam[1].translation();
  for (size_t i = 0; i < problem.points.size(); i += 5) {
    const Eigen::Vector3d& p = problem.points[i].p_world;
    problem.points[i].p_world = scene.T_world_cam[0].translation() + 0.7 * (p - scene.T_world_cam[0].translation());
  }
  problem.T_world_cam = scene.T_world_cam[1];
  PoseRefinerConfig config;
  config.point_outlier_threshold_px = 1e3;  // keep them all in: the weight alone decides
  const PoseRefiner refiner(config);
  const auto full = refiner.refine(problem);
  for (size_t i = 0; i < problem.points.size(); i += 5) problem.points[i].weight = 0.05;
  const auto weighted = refiner.refine(problem);
  ASSERT_TRUE(full.ok);
  ASSERT_TRUE(weighted.ok);
  const double e_full = translation_error(full.T_world_cam, scene.T_world_cam[1]);
  const double e_weighted = translation_error(weighted.T_world_cam, scene.T_world_cam[1]);
  std::printf("translation error: full weight %.4f, weight 0.05 %.5f (camera at %.2f from the origin)\n", e_full,
              e_weighted, centre.norm());
  EXPECT_GT(e_full, 0.01);
  EXPECT_LT(e_weighted, 0.1 * e_full);
}

TEST(PoseRefiner, DirectionsHoldTheRotationAgainstATurnedMap) {
  // The map's 20 points were placed by a camera turned 2 degrees (a drifted map): they alone
  // give the turned rotation; 30 segments along known world directions pull it most of the way
  // back to the truth.
  const auto scene = make_scene(1, 20, 0, 91);
  const Pose& T = scene.T_world_cam[0];
  const Eigen::Matrix3d turn = pllvo::geometry::so3_exp(Eigen::Vector3d(0.0, 2.0 * M_PI / 180, 0.0));
  const Pose T_turned = pllvo::geometry::make_pose(T.linear() * turn, T.translation());
  PoseRefinementProblem problem;
  problem.focal_px = kFocal;
  problem.T_world_cam = T_turned;
  std::mt19937 rng(3);
  for (const auto& p : scene.points) {
    Eigen::Vector2d xy;
    observe(T_turned, p, xy);
    problem.points.push_back({p, add_noise(xy, 0.3, rng), 0});
  }
  const std::vector<Eigen::Vector3d> dirs = {Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(),
                                             Eigen::Vector3d::UnitZ()};
  for (const auto& s : segments_along(T, dirs, 10, 0.3, rng))
    problem.directions.push_back({s.direction_world, s.start, s.end});
  PoseRefinerConfig config;
  config.point_outlier_threshold_px = 1e3;  // every point stays in: the test is about the pull
  const PoseRefiner refiner(config);
  const auto points_only = refiner.refine(problem);  // direction_weight 0: unused
  problem.direction_weight = 10.0;
  const auto with_directions = refiner.refine(problem);
  ASSERT_TRUE(points_only.ok && with_directions.ok);
  const double r_points = rotation_error_deg(points_only.T_world_cam, T);
  const double r_dirs = rotation_error_deg(with_directions.T_world_cam, T);
  std::printf("rotation error: points %.3f deg, with 30 segments on directions %.3f deg\n", r_points, r_dirs);
  EXPECT_GT(r_points, 1.8);
  EXPECT_LT(r_dirs, 0.3 * r_points);
}
