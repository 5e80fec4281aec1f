// Bench numbers: trajectory errors against known perturbations, stats.json parsing, median and
// spread over repeats, the table / CSV / JSON.
#include <cmath>

#include <gtest/gtest.h>

#include "pllvo/report/bench_table.h"
#include "pllvo/report/run_metrics.h"

namespace pllvo::report {
namespace {

io::Trajectory circle(size_t n, double radius, double dt = 0.05) {
  io::Trajectory t;
  for (size_t i = 0; i < n; ++i) {
    const double a = 2 * M_PI * i / n;
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    T.translation() = Eigen::Vector3d(radius * std::cos(a), radius * std::sin(a), 0.1 * std::sin(3 * a));
    t.push_back(100.0 + i * dt, T);
  }
  return t;
}

TEST(RunMetrics, RigidlyMovedEstimateHasZeroErrorWithSe3AndScaledWithSim3) {
  const auto gt = circle(200, 2.0);
  io::Trajectory est = gt;
  Eigen::Isometry3d M = Eigen::Isometry3d::Identity();
  M.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  M.translation() = Eigen::Vector3d(5, -1, 2);
  for (auto& T : est.poses) T = M * T;
  RunMetrics m;
  add_trajectory_errors(est, gt, true, 20, m);
  EXPECT_NEAR(m.ate_rmse_m, 0, 1e-9);
  EXPECT_NEAR(m.rpe_trans_m, 0, 1e-9);
  EXPECT_NEAR(m.rpe_rot_deg, 0, 1e-6);
  // Half the size (monocular scale): Sim3 removes it, SE3 cannot.
  for (auto& T : est.poses) T.translation() *= 0.5;
  RunMetrics sim, se;
  add_trajectory_errors(est, gt, false, 20, sim);
  add_trajectory_errors(est, gt, true, 20, se);
  EXPECT_NEAR(sim.ate_rmse_m, 0, 1e-9);
  EXPECT_GT(se.ate_rmse_m, 0.3);
}

TEST(RunMetrics, ConstantOffsetOnHalfThePosesGivesTheExpectedRmse) {
  const auto gt = circle(400, 2.0);
  io::Trajectory est = gt;
  // Alternate +d/-d along z: the alignment cannot remove it; every pose is off by d.
  const double d = 0.03;
  for (size_t i = 0; i < est.size(); ++i) est.poses[i].translation().z() += (i % 2 ? d : -d);
  RunMetrics m;
  add_trajectory_errors(est, gt, true, 1, m);
  EXPECT_NEAR(m.ate_rmse_m, d, 1e-4);
  EXPECT_NEAR(m.rpe_trans_m, 2 * d, 1e-3);  // consecutive poses are 2d apart in z
  EXPECT_GT(m.ate_percent, 0);
}

TEST(RunMetrics, AStraightLineReferenceStillGetsItsError) {
  // A slider's ground truth (ecd_slider_hdr_close_149): a straight line, which evo refuses to align.
  io::Trajectory gt, est;
  for (int i = 0; i < 100; ++i) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = Eigen::Vector3d(0.01 * i, 0, 0);
    gt.push_back(0.05 * i, T);
    T.translation().y() += (i % 2 ? 0.002 : -0.002);  // every pose 2 mm off the line
    est.push_back(0.05 * i, T);
  }
  RunMetrics m;
  add_trajectory_errors(est, gt, true, 1, m);
  EXPECT_NEAR(m.ate_rmse_m, 0.002, 1e-4);
  EXPECT_NEAR(m.ate_percent, 100 * 0.002 / 0.99, 0.01);
  EXPECT_NEAR(m.rpe_trans_m, 0.004, 5e-4);  // consecutive poses 4 mm apart across the line
}

TEST(RunMetrics, TooFewPosesLeaveNaN) {
  RunMetrics m;
  add_trajectory_errors(circle(2, 1), circle(100, 1), true, 1, m);
  EXPECT_TRUE(std::isnan(m.ate_rmse_m));
}

TEST(RunMetrics, ReadsCountsAndModuleTimesFromStatsJson) {
  const auto stats = nlohmann::json::parse(R"({
    "frames": 200, "tracked_frames": 150, "keyframes": 12, "resets": 1, "wall_time_s": 4.0,
    "timing_ms": {"frame": {"mean": 9.5, "median": 8.0, "p95": 20.0},
                  "kf_detect": {"mean": 30.0}, "klt": {"mean": 3.0}, "line_tracking": {"mean": 2.0},
                  "kf_match": {"mean": 4.0}, "kf_ba": {"mean": 50.0}}})");
  RunMetrics m;
  add_stats(stats, m);
  EXPECT_EQ(m.frames, 200);
  EXPECT_DOUBLE_EQ(m.tracked_share, 0.75);
  EXPECT_EQ(m.keyframes, 12);
  EXPECT_DOUBLE_EQ(m.wall_ms_per_frame, 20.0);
  EXPECT_DOUBLE_EQ(m.frame_ms_median, 8.0);
  EXPECT_DOUBLE_EQ(m.frame_ms_p95, 20.0);
  EXPECT_DOUBLE_EQ(m.module_ms["point_extraction"], 30.0);
  EXPECT_DOUBLE_EQ(m.module_ms["tracking"], 5.0);  // klt + line_tracking
  EXPECT_DOUBLE_EQ(m.module_ms["line_extraction"], 0.0);  // never ran
  EXPECT_DOUBLE_EQ(m.module_ms["ba"], 50.0);
}

TEST(Aggregate, MedianAndSpreadOfFiniteValues) {
  const auto a = aggregate({3, 1, NAN, 2, 10});
  EXPECT_EQ(a.n, 4u);
  EXPECT_DOUBLE_EQ(a.median, 2.5);
  EXPECT_DOUBLE_EQ(a.spread, 9);
  const auto b = aggregate({4, 1, 2});
  EXPECT_DOUBLE_EQ(b.median, 2);
  EXPECT_TRUE(std::isnan(aggregate({NAN}).median));
}

BenchResult fake_result() {
  BenchResult r;
  r.methods = {"orb", "pllvo"};
  r.sequences = {"s1", "s2"};
  r.repeat = 3;
  r.speed_baseline = "orb";
  for (const auto& s : r.sequences) {
    for (const auto& m : r.methods) {
      BenchCell c;
      c.method = m, c.sequence = s;
      const double f = m == "orb" ? 1.0 : 2.0;
      c.stats["ate_rmse_m"] = {0.01 * f, 0.002, 3};
      c.stats["tracked_share"] = {1.0, 0, 3};
      c.stats["wall_ms_per_frame"] = {10 * f, 1, 3};
      c.stats["speed_ratio"] = {f, 0.1, 3};
      c.runs.resize(3);
      r.cells.push_back(c);
    }
  }
  BenchCell failed;
  failed.method = "pllvo", failed.sequence = "s3";
  failed.runs.resize(1);
  failed.runs[0].error = "boom";
  failed.failed = 1, failed.error = "boom";
  r.sequences.push_back("s3");
  r.cells.push_back(failed);
  return r;
}

TEST(BenchTable, OneRowPerCellPlusMeansWithMedianAndSpread) {
  const auto r = fake_result();
  const std::string t = format_bench_table(r);
  EXPECT_NE(t.find("0.0100 (0.0020)"), std::string::npos) << t;
  EXPECT_NE(t.find("0.0200 (0.0020)"), std::string::npos) << t;
  EXPECT_NE(t.find("FAILED: boom"), std::string::npos) << t;
  EXPECT_NE(t.find("x orb"), std::string::npos);
  const auto means = method_means(r, "pllvo");
  EXPECT_DOUBLE_EQ(means.at("ate_rmse_m"), 0.02);
  EXPECT_DOUBLE_EQ(means.at("speed_ratio"), 2.0);
  size_t mean_rows = 0;
  for (size_t p = t.find("\nmean "); p != std::string::npos; p = t.find("\nmean ", p + 1)) ++mean_rows;
  EXPECT_EQ(mean_rows, 2u);
}

TEST(BenchTable, RealtimeRunsAddDroppedFramesAndLatency) {
  const auto stats = nlohmann::json::parse(R"({"frames": 200, "tracked_frames": 190,
    "realtime": {"frames_dropped": 10, "latency_mean_ms": 42.5, "latency_p95_ms": 90.0,
                 "keyframe_return_frames_mean": 6.5}})");
  RunMetrics m;
  add_stats(stats, m);
  EXPECT_DOUBLE_EQ(m.dropped_share, 0.05);
  EXPECT_DOUBLE_EQ(m.latency_mean_ms, 42.5);
  EXPECT_DOUBLE_EQ(m.latency_p95_ms, 90.0);
  EXPECT_DOUBLE_EQ(m.keyframe_return_frames, 6.5);
  RunMetrics offline;
  add_stats(nlohmann::json::parse(R"({"frames": 200})"), offline);
  EXPECT_TRUE(std::isnan(offline.dropped_share));

  auto r = fake_result();
  EXPECT_EQ(format_bench_table(r).find("dropped %"), std::string::npos);
  r.realtime = true;
  for (auto& c : r.cells)
    c.stats["dropped_share"] = {0.05, 0, 3}, c.stats["latency_mean_ms"] = {42.5, 1, 3},
    c.stats["keyframe_return_frames"] = {6.5, 0, 3};
  const std::string t = format_bench_table(r);
  EXPECT_NE(t.find("dropped %"), std::string::npos) << t;
  EXPECT_NE(t.find("kf back"), std::string::npos) << t;
  EXPECT_NE(t.find(" 6.5 "), std::string::npos) << t;
  EXPECT_NE(t.find(" 5.0 "), std::string::npos) << t;
  EXPECT_NE(t.find("42.5"), std::string::npos) << t;
}

TEST(BenchTable, CsvAndJsonHoldEveryCell) {
  const auto r = fake_result();
  const std::string csv = format_bench_csv(r);
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + 5);
  EXPECT_NE(csv.find("s1,orb,3,0"), std::string::npos) << csv;
  const auto j = bench_json(r, {});
  ASSERT_EQ(j["cells"].size(), 5u);
  EXPECT_DOUBLE_EQ(j["cells"][1]["median"]["ate_rmse_m"].get<double>(), 0.02);
  EXPECT_EQ(j["cells"][4]["error"], "boom");
  EXPECT_DOUBLE_EQ(j["mean_over_sequences"]["orb"]["wall_ms_per_frame"].get<double>(), 10.0);
}

}  // namespace
}  // namespace pllvo::report
