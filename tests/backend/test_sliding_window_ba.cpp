#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "../support/synthetic_scene.h"
#include "pllvo/backend/sliding_window_ba.h"

using namespace pllvo::backend;
using namespace pllvo::test;

namespace {
/// With `with_outliers`, observation (k, i) is an outlier when (7 k + i) % 10 == 0: 10% of
/// them, and at most one per landmark among 10 consecutive keyframes.
bool is_outlier(int k, int i) { return (7 * k + i) % 10 == 0; }

/// Every keyframe observes every landmark, with `sigma_px` noise; outliers are 15-40 px off.
BaProblem make_problem(const SyntheticScene& scene, double sigma_px, bool with_outliers, std::mt19937& rng) {
  BaProblem p;
  p.focal_px = kFocal;
  for (const auto& T : scene.T_world_cam) p.keyframes.push_back({T, false});
  for (const auto& x : scene.points) p.points.push_back({x, false});
  for (const auto& s : scene.lines) p.lines.push_back({s, false});
  std::uniform_real_distribution<double> angle(0, 2 * M_PI), offset(15, 40);
  for (int k = 0; k < static_cast<int>(scene.T_world_cam.size()); ++k) {
    for (int i = 0; i < static_cast<int>(scene.points.size()); ++i) {
      Eigen::Vector2d xy;
      observe(scene.T_world_cam[k], scene.points[i], xy);
      xy = add_noise(xy, sigma_px, rng);
      if (with_outliers && is_outlier(k, i)) {
        const double a = angle(rng);
        xy += offset(rng) / kFocal * Eigen::Vector2d(std::cos(a), std::sin(a));
      }
      p.point_observations.push_back({k, i, 0, xy});
    }
    for (int i = 0; i < static_cast<int>(scene.lines.size()); ++i) {
      Eigen::Vector3d l = observe_line(scene.T_world_cam[k], scene.lines[i], sigma_px, rng);
      if (with_outliers && is_outlier(k, i)) l.z() += (angle(rng) < M_PI ? 1 : -1) * offset(rng) / kFocal;
      p.line_observations.push_back({k, i, 0, l});
    }
  }
  return p;
}

Eigen::Vector3d random_offset(double sigma, std::mt19937& rng) {
  std::normal_distribution<double> n(0, sigma);
  return {n(rng), n(rng), n(rng)};
}

/// Moves keyframes from `first_free` on by ~`translation` / ~`rotation_deg`, and every
/// point and line endpoint by ~`landmark` (per axis, Gaussian).
void perturb(BaProblem& p, int first_free, double translation, double rotation_deg, double landmark, std::mt19937& rng) {
  for (size_t k = first_free; k < p.keyframes.size(); ++k) {
    Pose& T = p.keyframes[k].T_world_cam;
    const Eigen::Vector3d phi = random_offset(rotation_deg * M_PI / 180 / std::sqrt(3.0), rng);
    T = pllvo::geometry::make_pose(T.linear() * pllvo::geometry::so3_exp(phi),
                                   T.translation() + random_offset(translation / std::sqrt(3.0), rng));
  }
  if (landmark <= 0) return;
  for (auto& x : p.points) x.p_world += random_offset(landmark, rng);
  for (auto& l : p.lines) {
    l.segment_world.start += random_offset(landmark, rng);
    l.segment_world.end += random_offset(landmark, rng);
  }
}

struct Errors {
  double max_translation = 0, max_rotation_deg = 0, median_point = 0, median_line = 0;
};

Errors errors(const BaProblem& p, const SyntheticScene& truth) {
  Errors e;
  for (size_t k = 0; k < p.keyframes.size(); ++k) {
    e.max_translation = std::max(e.max_translation, translation_error(p.keyframes[k].T_world_cam, truth.T_world_cam[k]));
    e.max_rotation_deg = std::max(e.max_rotation_deg, rotation_error_deg(p.keyframes[k].T_world_cam, truth.T_world_cam[k]));
  }
  std::vector<double> pts, lines;
  for (size_t i = 0; i < p.points.size(); ++i) pts.push_back((p.points[i].p_world - truth.points[i]).norm());
  for (size_t i = 0; i < p.lines.size(); ++i)
    lines.push_back(std::max(distance_to_line(p.lines[i].segment_world.start, truth.lines[i]),
                             distance_to_line(p.lines[i].segment_world.end, truth.lines[i])));
  auto median = [](std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
  };
  e.median_point = median(pts);
  e.median_line = median(lines);
  return e;
}

void print(const char* what, const Errors& before, const Errors& after) {
  std::printf("[ bundle adjustment ] %s: pose %.2e m / %.2e deg -> %.2e m / %.2e deg, point %.2e -> %.2e m, "
              "line %.2e -> %.2e m\n",
              what, before.max_translation, before.max_rotation_deg, after.max_translation, after.max_rotation_deg,
              before.median_point, after.median_point, before.median_line, after.median_line);
}
}  // namespace

TEST(SlidingWindowBA, ConvergesToTruthAndKeepsFixedKeyframesFixed) {
  const auto scene = make_scene(8, 200, 40, 90);
  std::mt19937 rng(91);
  BaProblem problem = make_problem(scene, 0.0, false, rng);
  perturb(problem, 2, 0.05, 1.0, 0.1, rng);
  const BaProblem initial = problem;
  const Errors before = errors(problem, scene);

  BundleAdjustmentConfig config;
  config.num_fixed_oldest = 2;  // monocular: two fixed keyframes also fix the scale
  config.max_iterations = 30;
  const auto summary = SlidingWindowBA(config).optimize(problem);
  ASSERT_TRUE(summary.ok) << summary.report;
  const Errors after = errors(problem, scene);
  print("noise-free", before, after);
  EXPECT_EQ(summary.num_free_keyframes, 6);
  EXPECT_EQ(summary.num_free_points, 200);
  EXPECT_EQ(summary.num_free_lines, 40);
  EXPECT_LT(after.max_translation, 1e-4);
  EXPECT_LT(after.max_rotation_deg, 1e-3);
  EXPECT_LT(after.median_point, 1e-4);
  EXPECT_LT(after.median_line, 1e-4);
  EXPECT_EQ(summary.num_point_outliers, 0);
  EXPECT_EQ(summary.num_line_outliers, 0);
  EXPECT_GT(summary.initial_rms_px, 5.0);
  EXPECT_LT(summary.final_rms_px, 1e-3);
  EXPECT_LT(summary.final_cost, 1e-6 * summary.initial_cost);
  for (int k = 0; k < 2; ++k) EXPECT_EQ(problem.keyframes[k].T_world_cam.matrix(), initial.keyframes[k].T_world_cam.matrix());
  // Line endpoints move only across the line (their extent along it is kept).
  for (size_t i = 0; i < problem.lines.size(); ++i) {
    const auto& a = initial.lines[i].segment_world;
    const auto& b = problem.lines[i].segment_world;
    EXPECT_NEAR((b.start - a.start).dot(a.direction()), 0.0, 1e-12);
    EXPECT_NEAR((b.end - a.end).dot(a.direction()), 0.0, 1e-12);
  }
}

TEST(SlidingWindowBA, NoisyObservationsReachTheLeastSquaresSolution) {
  // With 0.5 px noise the optimum is not the truth: started from the perturbed state, BA must
  // reach the same optimum as started from the truth, and that optimum is near the truth.
  const auto scene = make_scene(8, 200, 40, 92);
  std::mt19937 rng(93);
  BaProblem from_truth = make_problem(scene, 0.5, false, rng);
  BaProblem problem = from_truth;
  perturb(problem, 2, 0.05, 1.0, 0.1, rng);
  const Errors before = errors(problem, scene);
  BundleAdjustmentConfig config;
  config.num_fixed_oldest = 2;
  config.max_iterations = 30;
  config.function_tolerance = 1e-10;
  const auto summary = SlidingWindowBA(config).optimize(problem);
  ASSERT_TRUE(summary.ok);
  ASSERT_TRUE(SlidingWindowBA(config).optimize(from_truth).ok);
  const Errors after = errors(problem, scene);
  print("0.5 px noise", before, after);
  // Same optimum, up to the solver's tolerance (well below the distance to the truth).
  const SyntheticScene reference{[&] {
    std::vector<Pose> T;
    for (const auto& kf : from_truth.keyframes) T.push_back(kf.T_world_cam);
    return T;
  }(), [&] {
    std::vector<Eigen::Vector3d> x;
    for (const auto& p : from_truth.points) x.push_back(p.p_world);
    return x;
  }(), [&] {
    std::vector<LineSegment3d> l;
    for (const auto& line : from_truth.lines) l.push_back(line.segment_world);
    return l;
  }()};
  const Errors gap = errors(problem, reference);
  EXPECT_LT(gap.max_translation, 1e-3);
  EXPECT_LT(gap.max_rotation_deg, 0.01);
  EXPECT_LT(gap.median_point, 1e-3);
  EXPECT_LT(gap.median_line, 1e-3);
  EXPECT_LT(after.max_translation, 0.02);
  EXPECT_LT(after.max_rotation_deg, 0.1);
  EXPECT_LT(after.median_point, 0.03);
  EXPECT_LT(after.median_line, 0.06);
  // Residuals at the noise level: 0.5 px per coordinate, a bit less after fitting.
  EXPECT_GT(summary.final_rms_px, 0.4);
  EXPECT_LT(summary.final_rms_px, 0.75);
  EXPECT_LE(summary.num_point_outliers, 2);
}

TEST(SlidingWindowBA, OutliersAreDownWeightedAndFlagged) {
  const auto scene = make_scene(8, 200, 40, 94);
  std::mt19937 rng(95);
  BaProblem problem = make_problem(scene, 0.5, true, rng);
  perturb(problem, 2, 0.03, 0.5, 0.05, rng);
  BaProblem plain_problem = problem;

  BundleAdjustmentConfig config;
  config.num_fixed_oldest = 2;
  config.max_iterations = 20;
  const auto summary = SlidingWindowBA(config).optimize(problem);
  ASSERT_TRUE(summary.ok);
  const Errors robust = errors(problem, scene);

  int missed = 0, false_alarms = 0, outliers = 0;
  for (size_t j = 0; j < problem.point_observations.size(); ++j) {
    const auto& o = problem.point_observations[j];
    const bool outlier = is_outlier(o.keyframe, o.point);
    outliers += outlier;
    missed += outlier && !summary.point_outliers[j];
    false_alarms += !outlier && summary.point_outliers[j];
  }
  EXPECT_EQ(missed, 0);
  EXPECT_LE(false_alarms, 0.01 * (problem.point_observations.size() - outliers));
  for (size_t j = 0; j < problem.line_observations.size(); ++j) {
    const auto& o = problem.line_observations[j];
    EXPECT_EQ(summary.line_outliers[j], is_outlier(o.keyframe, o.line)) << "line observation " << j;
  }

  config.point_loss.type = config.line_loss.type = LossType::kNone;
  config.second_pass = false;
  ASSERT_TRUE(SlidingWindowBA(config).optimize(plain_problem).ok);
  const Errors plain = errors(plain_problem, scene);
  std::printf("[ bundle adjustment, 10%% outliers ] robust: pose %.4f m %.4f deg, point %.4f m, line %.4f m; "
              "least squares: pose %.4f m %.4f deg, point %.4f m, line %.4f m\n",
              robust.max_translation, robust.max_rotation_deg, robust.median_point, robust.median_line,
              plain.max_translation, plain.max_rotation_deg, plain.median_point, plain.median_line);
  EXPECT_LT(robust.max_translation, 0.01);
  EXPECT_LT(robust.median_point, 0.03);
  EXPECT_GT(plain.max_translation, 2 * robust.max_translation);
  EXPECT_GT(plain.median_point, 2 * robust.median_point);
}

TEST(SlidingWindowBA, OnlyTheNewestWindowMoves) {
  const auto scene = make_scene(12, 150, 20, 96, 0.2);
  std::mt19937 rng(97);
  BaProblem problem = make_problem(scene, 0.0, false, rng);
  perturb(problem, 7, 0.05, 1.0, 0.0, rng);  // only the window's poses are off,
  problem.keyframes[9] = {scene.T_world_cam[9], true};  // except one the caller pins
  const BaProblem initial = problem;
  BundleAdjustmentConfig config;
  config.window_size = 5;
  config.max_iterations = 30;
  const SlidingWindowBA ba(config);
  for (int k = 0; k < 12; ++k) EXPECT_EQ(ba.keyframe_fixed(k, 12, problem.keyframes[k].fixed), k < 7 || k == 9) << k;
  const auto summary = ba.optimize(problem);
  ASSERT_TRUE(summary.ok);
  EXPECT_EQ(summary.num_free_keyframes, 4);
  for (int k : {0, 1, 2, 3, 4, 5, 6, 9})
    EXPECT_EQ(problem.keyframes[k].T_world_cam.matrix(), initial.keyframes[k].T_world_cam.matrix()) << k;
  for (int k : {7, 8, 10, 11}) {
    EXPECT_LT(translation_error(problem.keyframes[k].T_world_cam, scene.T_world_cam[k]), 1e-5) << k;
    EXPECT_LT(rotation_error_deg(problem.keyframes[k].T_world_cam, scene.T_world_cam[k]), 1e-4) << k;
  }
}

TEST(SlidingWindowBA, AnalyticAndAutodiffJacobiansGiveTheSameSolution) {
  const auto scene = make_scene(5, 80, 15, 98);
  std::mt19937 rng(99);
  BaProblem a = make_problem(scene, 0.5, false, rng);
  perturb(a, 1, 0.03, 0.5, 0.05, rng);
  BaProblem b = a;
  BundleAdjustmentConfig config;
  const auto sa = SlidingWindowBA(config).optimize(a);
  config.jacobians = BaJacobians::kAutodiff;
  const auto sb = SlidingWindowBA(config).optimize(b);
  EXPECT_EQ(sa.iterations, sb.iterations);
  EXPECT_NEAR(sa.final_cost, sb.final_cost, 1e-8 * sa.final_cost);
  for (size_t k = 0; k < a.keyframes.size(); ++k)
    EXPECT_LT((a.keyframes[k].T_world_cam.matrix() - b.keyframes[k].T_world_cam.matrix()).norm(), 1e-8);
  for (size_t i = 0; i < a.points.size(); ++i) EXPECT_LT((a.points[i].p_world - b.points[i].p_world).norm(), 1e-7);
}

TEST(SlidingWindowBA, StereoObservationsFixTheScaleWithOneFixedKeyframe) {
  const auto scene = make_scene(5, 100, 20, 100);
  std::mt19937 rng(101);
  const Pose T_right_left = pllvo::geometry::make_pose(Eigen::Matrix3d::Identity(), Eigen::Vector3d(-0.11, 0, 0));
  BaProblem problem = make_problem(scene, 0.0, false, rng);
  problem.T_cam_cam0 = {Pose::Identity(), T_right_left};
  for (int k = 0; k < 5; ++k) {
    const Pose T_right = scene.T_world_cam[k] * T_right_left.inverse();
    for (int i = 0; i < 100; ++i) {
      Eigen::Vector2d xy;
      if (!observe(T_right, scene.points[i], xy)) continue;
      problem.point_observations.push_back({k, i, 1, xy});
    }
  }
  perturb(problem, 1, 0.05, 1.0, 0.1, rng);
  BundleAdjustmentConfig config;
  config.num_fixed_oldest = 1;
  config.max_iterations = 30;
  const auto summary = SlidingWindowBA(config).optimize(problem);
  ASSERT_TRUE(summary.ok);
  const Errors after = errors(problem, scene);
  EXPECT_EQ(summary.num_free_keyframes, 4);
  EXPECT_LT(after.max_translation, 1e-4);
  EXPECT_LT(after.median_point, 1e-4);
}

/// The stereo scene above with every right observation shifted by `offset_px` along x: a
/// rectification whose right principal point is off by that much.
BaProblem stereo_problem_with_offset(const SyntheticScene& scene, double offset_px, std::mt19937& rng) {
  const Pose T_right_left = pllvo::geometry::make_pose(Eigen::Matrix3d::Identity(), Eigen::Vector3d(-0.11, 0, 0));
  BaProblem problem = make_problem(scene, 0.3, false, rng);
  problem.T_cam_cam0 = {Pose::Identity(), T_right_left};
  for (int k = 0; k < static_cast<int>(scene.T_world_cam.size()); ++k) {
    const Pose T_right = scene.T_world_cam[k] * T_right_left.inverse();
    for (int i = 0; i < static_cast<int>(scene.points.size()); ++i) {
      Eigen::Vector2d xy;
      if (!observe(T_right, scene.points[i], xy)) continue;
      xy = add_noise(xy, 0.3, rng) + Eigen::Vector2d(offset_px / kFocal, 0);
      problem.point_observations.push_back({k, i, 1, xy});
    }
  }
  perturb(problem, 1, 0.05, 1.0, 0.1, rng);
  return problem;
}

TEST(SlidingWindowBA, EstimatesTheStereoPairsHorizontalOffsetAndKeepsTheScale) {
  // 0.8 px of disparity error: estimated to within 0.1 px; held at 0 instead, the same data
  // gives a map and poses several times further off.
  const auto scene = make_scene(8, 150, 0, 106);
  std::mt19937 rng(107);
  BaProblem estimated = stereo_problem_with_offset(scene, 0.8, rng);
  BaProblem held = estimated;
  BundleAdjustmentConfig config;
  config.max_iterations = 50;
  const auto summary = SlidingWindowBA(config).optimize(estimated);
  ASSERT_TRUE(summary.ok);
  EXPECT_NEAR(estimated.stereo_offset_px, 0.8, 0.1);
  config.stereo_offset_sigma_px = 0;
  ASSERT_TRUE(SlidingWindowBA(config).optimize(held).ok);
  EXPECT_EQ(held.stereo_offset_px, 0.0);
  const Errors with = errors(estimated, scene), without = errors(held, scene);
  std::printf("[ stereo offset ] estimated %.3f px; max translation error %.4f (estimated) vs %.4f (held at 0)\n",
              estimated.stereo_offset_px, with.max_translation, without.max_translation);
  EXPECT_LT(with.max_translation * 3, without.max_translation);
  EXPECT_LT(with.median_point * 3, without.median_point);
}

TEST(SlidingWindowBA, StereoOffsetHeldByItsPriorWithoutMotion) {
  // Keyframes at one place: the offset cannot be told from the depths; the prior keeps it at 0.
  auto scene = make_scene(4, 120, 0, 108);
  for (auto& T : scene.T_world_cam) T = scene.T_world_cam[0];
  std::mt19937 rng(109);
  BaProblem problem = stereo_problem_with_offset(scene, 0.0, rng);
  BundleAdjustmentConfig config;
  config.max_iterations = 30;
  ASSERT_TRUE(SlidingWindowBA(config).optimize(problem).ok);
  EXPECT_LT(std::abs(problem.stereo_offset_px), 0.05);
}

TEST(SlidingWindowBA, DistanceGaugeFreesTheSecondKeyframeButKeepsTheScale) {
  // A monocular start: keyframe 1 off by 1 deg of rotation and 10 deg of translation
  // direction, at the right distance from keyframe 0. Fixing it (two fixed keyframes) keeps
  // those errors; the distance gauge corrects them and keeps the distance, hence the scale.
  const auto scene = make_scene(6, 150, 0, 104);
  std::mt19937 rng(105);
  BaProblem fixed_pose = make_problem(scene, 0.0, false, rng);
  perturb(fixed_pose, 2, 0.05, 1.0, 0.1, rng);
  const Eigen::Vector3d c0 = scene.T_world_cam[0].translation();
  Pose& T1 = fixed_pose.keyframes[1].T_world_cam;
  const Eigen::Matrix3d turn = pllvo::geometry::so3_exp(Eigen::Vector3d(0, 10 * M_PI / 180, 0));
  T1 = pllvo::geometry::make_pose(T1.linear() * pllvo::geometry::so3_exp(Eigen::Vector3d(1 * M_PI / 180, 0, 0)),
                                  c0 + turn * (T1.translation() - c0));
  BaProblem distance = fixed_pose;
  const double d0 = (T1.translation() - c0).norm();

  BundleAdjustmentConfig config;
  config.max_iterations = 50;
  config.num_fixed_oldest = 2;
  const auto a = SlidingWindowBA(config).optimize(fixed_pose);
  config.num_fixed_oldest = 1;
  config.distance_gauge = true;
  const SlidingWindowBA gauged(config);
  EXPECT_EQ(gauged.distance_gauge_pair(distance), std::make_pair(0, 1));
  const auto b = gauged.optimize(distance);
  ASSERT_TRUE(a.ok && b.ok);
  EXPECT_EQ(a.num_free_keyframes, 4);
  EXPECT_EQ(b.num_free_keyframes, 5);
  const Errors with_fixed_pose = errors(fixed_pose, scene), with_distance = errors(distance, scene);
  print("second keyframe fixed", with_fixed_pose, with_distance);
  EXPECT_GT(with_fixed_pose.max_rotation_deg, 0.5);
  EXPECT_GT(with_fixed_pose.median_point, 0.05);
  EXPECT_LT(with_distance.max_translation, 1e-4);
  EXPECT_LT(with_distance.max_rotation_deg, 1e-3);
  EXPECT_LT(with_distance.median_point, 1e-3);
  EXPECT_NEAR((distance.keyframes[1].T_world_cam.translation() - c0).norm(), d0, 1e-6 * d0);

  // Two keyframes already fixed (the caller's anchors): no gauge.
  distance.keyframes[0].fixed = distance.keyframes[1].fixed = true;
  EXPECT_EQ(gauged.distance_gauge_pair(distance), std::make_pair(-1, -1));
  distance.keyframes[1].fixed = false;
  distance.keyframes[3].fixed = true;
  EXPECT_EQ(gauged.distance_gauge_pair(distance), std::make_pair(-1, -1));
  // A free keyframe that sees nothing cannot hold the scale: the next one does.
  distance.keyframes[3].fixed = false;
  std::erase_if(distance.point_observations, [](const BaPointObservation& o) { return o.keyframe == 1; });
  EXPECT_EQ(gauged.distance_gauge_pair(distance), std::make_pair(0, 2));
}

TEST(SlidingWindowBA, EdgeCases) {
  const auto scene = make_scene(3, 10, 2, 102);
  std::mt19937 rng(103);
  BaProblem problem = make_problem(scene, 0.0, false, rng);
  // A point seen once is held fixed; an observation behind its camera is skipped and flagged.
  problem.points.push_back({Eigen::Vector3d(0, 0, 5), false});
  problem.point_observations.push_back({2, 10, 0, Eigen::Vector2d(0.1, 0.0)});
  problem.points.push_back({Eigen::Vector3d(0, 0, -5), false});
  problem.point_observations.push_back({1, 11, 0, Eigen::Vector2d(0.0, 0.0)});
  problem.point_observations.push_back({2, 11, 0, Eigen::Vector2d(0.0, 0.0)});
  const auto summary = SlidingWindowBA().optimize(problem);
  ASSERT_TRUE(summary.ok);
  EXPECT_EQ(problem.points[10].p_world, Eigen::Vector3d(0, 0, 5));
  EXPECT_EQ(summary.num_free_points, 10);
  EXPECT_TRUE(summary.point_outliers.back());
  EXPECT_TRUE(summary.point_outliers[summary.point_outliers.size() - 2]);

  problem.point_observations.push_back({3, 0, 0, Eigen::Vector2d::Zero()});  // no keyframe 3
  EXPECT_THROW(SlidingWindowBA().optimize(problem), pllvo::InternalError);

  BaProblem empty;
  EXPECT_TRUE(SlidingWindowBA().optimize(empty).ok);
}

TEST(SlidingWindowBA, DirectionsTurnAKeyframeBackToItsTrueRotation) {
  // Keyframe 1 sees nothing but segments along known directions, from a pose turned 3 degrees:
  // their vanishing-point errors alone bring its rotation back.
  const auto scene = make_scene(2, 20, 0, 93);
  std::mt19937 rng(4);
  BaProblem p;
  p.focal_px = kFocal;
  p.direction_weight = 1.0;
  p.keyframes.push_back({scene.T_world_cam[0], false});
  const Pose& T1 = scene.T_world_cam[1];
  const Eigen::Matrix3d turn = pllvo::geometry::so3_exp(Eigen::Vector3d(0.02, -0.04, 0.03));
  // Turned about its own centre in the pose block's frame (T_cam_world keeps its translation).
  const Pose T1_cw = T1.inverse();
  const Pose T1_turned = pllvo::geometry::make_pose(turn * T1_cw.linear(), T1_cw.translation()).inverse();
  p.keyframes.push_back({T1_turned, false});
  const std::vector<Eigen::Vector3d> dirs = {Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(),
                                             Eigen::Vector3d::UnitZ()};
  for (const auto& s : segments_along(T1, dirs, 8, 0.0, rng)) p.direction_observations.push_back({1, s.direction_world, s.start, s.end});
  const double before = rotation_error_deg(p.keyframes[1].T_world_cam, T1);
  const auto summary = SlidingWindowBA().optimize(p);
  ASSERT_TRUE(summary.ok) << summary.report;
  EXPECT_GT(before, 2.5);
  EXPECT_LT(rotation_error_deg(p.keyframes[1].T_world_cam, T1), 1e-3);
  // A direction does not see the translation: T_cam_world's (the pose block's) stays.
  EXPECT_LT((p.keyframes[1].T_world_cam.inverse().translation() - T1.inverse().translation()).norm(), 1e-9);
  // direction_weight 0: the observations are not used.
  BaProblem off = p;
  off.direction_weight = 0;
  off.keyframes[1].T_world_cam = T1_turned;
  SlidingWindowBA().optimize(off);
  EXPECT_GT(rotation_error_deg(off.keyframes[1].T_world_cam, T1), 2.5);
  // An observation naming a keyframe that does not exist is a programming error.
  BaProblem bad = p;
  bad.direction_observations.push_back({5, Eigen::Vector3d::UnitX(), {0, 0}, {0.1, 0}});
  EXPECT_THROW(SlidingWindowBA().optimize(bad), pllvo::InternalError);
}
