// Back-end speed, single thread: sliding-window bundle adjustment (10 keyframes, 1000
// points, 100 lines) with analytic Jacobians against the same solve with Ceres autodiff
// (the baseline), and the hand-written per-frame pose refinement against the same
// problem solved by Ceres. Run: build/bin/bench_backend --benchmark_repetitions=3
#include <benchmark/benchmark.h>

#include <ceres/ceres.h>

#include "../tests/support/synthetic_scene.h"
#include "pllvo/backend/ba_costs.h"
#include "pllvo/backend/pose_refiner.h"
#include "pllvo/backend/sliding_window_ba.h"

using namespace pllvo::backend;
using namespace pllvo::test;

namespace {
constexpr int kKeyframes = 10, kPoints = 1000, kLines = 100;

Eigen::Vector3d gaussian(double sigma, std::mt19937& rng) {
  std::normal_distribution<double> n(0, sigma);
  return {n(rng), n(rng), n(rng)};
}

/// A window of 10 keyframes 0.25 m apart; every landmark is observed by the keyframes that
/// see it (3 to 10 of them), 0.5 px noise, 3% outliers (15-40 px off); poses and landmarks
/// perturbed.
const BaProblem& window_problem() {
  static const BaProblem problem = [] {
    std::mt19937 rng(7);
    BaProblem p;
    p.focal_px = kFocal;
    for (int k = 0; k < kKeyframes; ++k)
      p.keyframes.push_back({random_rotation_pose(rng, Eigen::Vector3d(0.25 * k, 0.05 * std::sin(k), 0.1 * k), 3.0), false});
    std::uniform_real_distribution<double> ux(-3, 5.5), uy(-2, 2), uz(3, 12), len(0.8, 2.5), outlier(0, 1),
        offset(15, 40);
    auto observers = [&](const Eigen::Vector3d& x) {
      std::vector<int> ks;
      for (int k = 0; k < kKeyframes; ++k)
        if (in_view(p.keyframes[k].T_world_cam, x)) ks.push_back(k);
      return ks;
    };
    while (static_cast<int>(p.points.size()) < kPoints) {
      const Eigen::Vector3d x(ux(rng), uy(rng), uz(rng));
      const auto ks = observers(x);
      if (ks.size() < 3) continue;
      const int id = static_cast<int>(p.points.size());
      p.points.push_back({x, false});
      for (int k : ks) {
        Eigen::Vector2d xy;
        observe(p.keyframes[k].T_world_cam, x, xy);
        xy = add_noise(xy, 0.5, rng);
        if (outlier(rng) < 0.03) xy.x() += offset(rng) / kFocal;
        p.point_observations.push_back({k, id, 0, xy});
      }
    }
    while (static_cast<int>(p.lines.size()) < kLines) {
      const Eigen::Vector3d a(ux(rng), uy(rng), uz(rng));
      const LineSegment3d s{a, a + len(rng) * gaussian(1.0, rng).normalized()};
      std::vector<int> ks;
      for (int k : observers(s.start))
        if (in_view(p.keyframes[k].T_world_cam, s.end)) ks.push_back(k);
      if (ks.size() < 3) continue;
      const int id = static_cast<int>(p.lines.size());
      p.lines.push_back({s, false});
      for (int k : ks) {
        Eigen::Vector3d l = observe_line(p.keyframes[k].T_world_cam, s, 0.5, rng);
        if (outlier(rng) < 0.03) l.z() += offset(rng) / kFocal;
        p.line_observations.push_back({k, id, 0, l});
      }
    }
    for (int k = 2; k < kKeyframes; ++k) {
      Pose& T = p.keyframes[k].T_world_cam;
      T = pllvo::geometry::make_pose(T.linear() * pllvo::geometry::so3_exp(gaussian(0.005, rng)),
                                     T.translation() + gaussian(0.02, rng));
    }
    for (auto& x : p.points) x.p_world += gaussian(0.05, rng);
    for (auto& l : p.lines) l.segment_world.start += gaussian(0.05, rng), l.segment_world.end += gaussian(0.05, rng);
    return p;
  }();
  return problem;
}

void run_ba(benchmark::State& state, BaJacobians jacobians, BaLinearSolver solver) {
  BundleAdjustmentConfig config;
  config.num_fixed_oldest = 2;
  config.jacobians = jacobians;
  config.linear_solver = solver;
  const SlidingWindowBA ba(config);
  BaSummary summary;
  for (auto _ : state) {
    BaProblem problem = window_problem();  // copying is ~1% of a solve
    summary = ba.optimize(problem);
    benchmark::DoNotOptimize(problem.points.data());
  }
  state.counters["iterations"] = summary.iterations;
  state.counters["rms_px_before"] = summary.initial_rms_px;
  state.counters["rms_px_after"] = summary.final_rms_px;
  state.counters["outliers"] = summary.num_point_outliers + summary.num_line_outliers;
  state.counters["observations"] =
      static_cast<double>(window_problem().point_observations.size() + window_problem().line_observations.size());
}

void BM_BundleAdjustment_Analytic(benchmark::State& state) {
  run_ba(state, BaJacobians::kAnalytic, BaLinearSolver::kDenseSchur);
}
void BM_BundleAdjustment_AutodiffBaseline(benchmark::State& state) {
  run_ba(state, BaJacobians::kAutodiff, BaLinearSolver::kDenseSchur);
}
void BM_BundleAdjustment_AnalyticSparseSchur(benchmark::State& state) {
  run_ba(state, BaJacobians::kAnalytic, BaLinearSolver::kSparseSchur);
}

/// One frame's tracking problem: 200 points and 40 lines, 0.7 px noise, 20% outliers, the
/// initial pose 5 cm / 2 deg off.
const PoseRefinementProblem& frame_problem() {
  static const PoseRefinementProblem problem = [] {
    const auto scene = make_scene(1, 200, 40, 11);
    std::mt19937 rng(12);
    std::uniform_real_distribution<double> offset(15, 40);
    PoseRefinementProblem p;
    p.focal_px = kFocal;
    const Pose& T = scene.T_world_cam[0];
    for (size_t i = 0; i < scene.points.size(); ++i) {
      Eigen::Vector2d xy;
      observe(T, scene.points[i], xy);
      xy = add_noise(xy, 0.7, rng);
      if (i % 5 == 0) xy.x() += offset(rng) / kFocal;
      p.points.push_back({scene.points[i], xy, 0});
    }
    for (size_t i = 0; i < scene.lines.size(); ++i) {
      Eigen::Vector3d l = observe_line(T, scene.lines[i], 0.7, rng);
      if (i % 5 == 0) l.z() += offset(rng) / kFocal;
      p.lines.push_back({scene.lines[i].start, scene.lines[i].end, l, 0});
    }
    p.T_world_cam = pllvo::geometry::make_pose(T.linear() * pllvo::geometry::so3_exp(Eigen::Vector3d(0.02, -0.02, 0.01)),
                                               T.translation() + Eigen::Vector3d(0.03, -0.03, 0.02));
    return p;
  }();
  return problem;
}

void BM_PoseRefiner(benchmark::State& state) {
  const PoseRefiner refiner;
  PoseRefinementResult r;
  for (auto _ : state) {
    r = refiner.refine(frame_problem());
    benchmark::DoNotOptimize(r.T_world_cam);
  }
  state.counters["iterations"] = r.iterations;
  state.counters["inliers"] = r.num_point_inliers + r.num_line_inliers;
}

/// The same problem as one Ceres solve (pose block only, landmarks constant, Huber, the
/// analytic residuals of the bundle adjustment): what the refiner would cost built on Ceres.
void BM_PoseRefiner_CeresBaseline(benchmark::State& state) {
  const auto& f = frame_problem();
  for (auto _ : state) {
    double pose[7];
    pose_to_block(f.T_world_cam.inverse(), pose);
    std::vector<Eigen::Vector3d> points;
    std::vector<std::array<double, 6>> lines;
    points.reserve(f.points.size());
    lines.reserve(f.lines.size());
    ceres::Problem problem;
    ceres::LossFunction* loss = new ceres::HuberLoss(2.0);
    for (const auto& o : f.points) {
      points.push_back(o.p_world);
      problem.AddResidualBlock(new PointReprojectionCost(o.xy, Pose::Identity(), f.focal_px), loss, pose,
                               points.back().data());
      problem.SetParameterBlockConstant(points.back().data());
    }
    for (const auto& o : f.lines) {
      lines.push_back({o.start_world.x(), o.start_world.y(), o.start_world.z(), o.end_world.x(), o.end_world.y(),
                       o.end_world.z()});
      problem.AddResidualBlock(new LineReprojectionCost(o.line, Pose::Identity(), f.focal_px), loss, pose,
                               lines.back().data());
      problem.SetParameterBlockConstant(lines.back().data());
    }
    problem.SetManifold(pose, new_pose_manifold());
    ceres::Solver::Options options;
    options.linear_solver_type = ceres::DENSE_QR;
    options.max_num_iterations = 20;
    options.num_threads = 1;
    options.logging_type = ceres::SILENT;
    ceres::Solver::Summary summary;
    ceres::Solve(options, &problem, &summary);
    benchmark::DoNotOptimize(pose);
  }
}

BENCHMARK(BM_BundleAdjustment_Analytic)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_BundleAdjustment_AutodiffBaseline)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_BundleAdjustment_AnalyticSparseSchur)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PoseRefiner)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_PoseRefiner_CeresBaseline)->Unit(benchmark::kMicrosecond);
}  // namespace

BENCHMARK_MAIN();
