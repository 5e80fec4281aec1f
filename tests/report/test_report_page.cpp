// The report page: alignment and angle series behind the plots, loading a run folder, and the
// page itself rendered by headless Chromium, checked on the screenshot for drawn plots.
#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "pllvo/common/error.h"
#include "pllvo/report/report_page.h"

namespace pllvo::report {
namespace {

namespace fs = std::filesystem;

io::Trajectory wavy_path(size_t n) {
  io::Trajectory t;
  for (size_t i = 0; i < n; ++i) {
    const double a = 2 * M_PI * i / n;
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = (Eigen::AngleAxisd(2.5 * a, Eigen::Vector3d::UnitZ()) *  // yaw passes +-180
                  Eigen::AngleAxisd(0.2 * std::sin(a), Eigen::Vector3d::UnitY()) *
                  Eigen::AngleAxisd(0.1 * std::cos(2 * a), Eigen::Vector3d::UnitX()))
                     .toRotationMatrix();
    T.translation() = Eigen::Vector3d(3 * std::cos(a), 2 * std::sin(a), 1 + 0.3 * std::sin(2 * a));
    t.push_back(10.0 + 0.05 * i, T);
  }
  return t;
}

TEST(RollPitchYaw, RoundTripsAndUnwraps) {
  const double r = 0.3, p = -0.4, y = 2.9;
  const Eigen::Matrix3d R = (Eigen::AngleAxisd(y, Eigen::Vector3d::UnitZ()) *
                             Eigen::AngleAxisd(p, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(r, Eigen::Vector3d::UnitX()))
                                .toRotationMatrix();
  const auto e = roll_pitch_yaw_deg(R);
  EXPECT_NEAR(e[0], r * 180 / M_PI, 1e-9);
  EXPECT_NEAR(e[1], p * 180 / M_PI, 1e-9);
  EXPECT_NEAR(e[2], y * 180 / M_PI, 1e-9);
  std::vector<double> a = {170, 179, -178, -170, 175, 10};
  unwrap_degrees(a);
  EXPECT_DOUBLE_EQ(a[2], 182);
  EXPECT_DOUBLE_EQ(a[3], 190);
  EXPECT_DOUBLE_EQ(a[4], 175);
  EXPECT_DOUBLE_EQ(a[5], 10);
}

TEST(PlotSeries, EstimateInAnotherFrameIsAlignedOntoTheGroundTruth) {
  const auto gt = wavy_path(200);
  io::Trajectory est = gt;
  Eigen::Isometry3d M = Eigen::Isometry3d::Identity();
  M.linear() = Eigen::AngleAxisd(1.1, Eigen::Vector3d(0.2, 1, 0.4).normalized()).toRotationMatrix();
  M.translation() = Eigen::Vector3d(-4, 2, 7);
  for (auto& T : est.poses) T = M * T;
  est.stamps.erase(est.stamps.begin(), est.stamps.begin() + 10);  // lost start
  est.poses.erase(est.poses.begin(), est.poses.begin() + 10);
  const auto s = plot_series(est, gt, true);
  ASSERT_EQ(s.t.size(), 190u);
  ASSERT_EQ(s.gt_xyz.size(), 190u);
  EXPECT_EQ(s.align, "se3");
  EXPECT_NEAR(s.ate_rmse_m, 0, 1e-9);
  EXPECT_DOUBLE_EQ(s.t.front(), 0.0);
  EXPECT_NEAR(s.t.back(), 189 * 0.05, 1e-9);
  for (size_t i = 0; i < s.t.size(); i += 17) {
    EXPECT_NEAR((s.est_xyz[i] - gt.poses[i + 10].translation()).norm(), 0, 1e-9);
    EXPECT_NEAR((s.est_rpy[i] - s.gt_rpy[i]).norm(), 0, 1e-6);
  }
  // Yaw turns 2.5 times round: unwrapped, it rises steadily past 180 degrees.
  EXPECT_GT(s.gt_rpy.back()[2] - s.gt_rpy.front()[2], 700);
  for (size_t i = 1; i < s.gt_rpy.size(); ++i) EXPECT_LT(std::abs(s.gt_rpy[i][2] - s.gt_rpy[i - 1][2]), 180);
}

TEST(PlotSeries, WithoutGroundTruthShowsTheEstimateAsItIs) {
  const auto est = wavy_path(50);
  const auto s = plot_series(est, std::nullopt, true);
  EXPECT_EQ(s.align, "none");
  EXPECT_TRUE(s.gt_xyz.empty());
  EXPECT_TRUE(s.error_m.empty());
  ASSERT_EQ(s.est_xyz.size(), 50u);
  EXPECT_NEAR((s.est_xyz[7] - est.poses[7].translation()).norm(), 0, 1e-12);
}

TEST(Base64, KnownVectors) {
  EXPECT_EQ(base64_encode(""), "");
  EXPECT_EQ(base64_encode("M"), "TQ==");
  EXPECT_EQ(base64_encode("Ma"), "TWE=");
  EXPECT_EQ(base64_encode("Man"), "TWFu");
  EXPECT_EQ(base64_encode(std::string("\xff\x00\x10", 3)), "/wAQ");
}

/// A run folder like `pllvo run --out --report` writes: the estimate is the ground truth
/// moved and slightly perturbed; one magenta frame image.
fs::path make_run_dir(const std::string& name, const io::Trajectory& gt) {
  const fs::path dir = fs::temp_directory_path() / ("pllvo_report_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir / "frames");
  io::Trajectory est = gt;
  for (size_t i = 0; i < est.size(); ++i) est.poses[i].translation() += Eigen::Vector3d(0.5, 0.2, 0.05 * std::sin(0.3 * i));
  io::write_tum(est, dir / "trajectory.tum");
  io::write_tum(gt, dir / "groundtruth.tum");
  std::ofstream(dir / "stats.json") << R"({"sequence": "/nonexistent/seq", "format": "euroc", "mode": "stereo",
    "frontend": "orb", "frames": 200, "tracked_frames": 200, "keyframes": 20, "resets": 0, "frames_per_second": 25.0,
    "timing_ms": {"frame": {"count": 200, "mean": 12.0, "p95": 30.0}, "klt": {"count": 200, "mean": 4.0, "p95": 6.0},
                  "kf_ba": {"count": 20, "mean": 60.0, "p95": 90.0}}})";
  cv::Mat frame(240, 376, CV_8UC3, cv::Scalar(255, 0, 255));  // magenta (BGR)
  cv::imwrite((dir / "frames" / "frame_17.png").string(), frame);
  return dir;
}

TEST(LoadRun, ReadsTheFolderAndNotesAMissingDataset) {
  const auto gt = wavy_path(200);
  const auto dir = make_run_dir("load", gt);
  const auto in = load_run(dir);
  EXPECT_EQ(in.estimate.size(), 200u);
  EXPECT_FALSE(in.ground_truth);  // the dataset path does not exist...
  EXPECT_NE(in.note.find("--ground-truth"), std::string::npos);  // ...and the page says how to give it
  EXPECT_TRUE(in.metric_scale);
  ASSERT_EQ(in.frames.size(), 1u);
  const auto with_gt = load_run(dir, dir / "groundtruth.tum");
  ASSERT_TRUE(with_gt.ground_truth);
  EXPECT_EQ(with_gt.ground_truth->size(), 200u);
}

TEST(LoadRun, MissingFolderOrFilesAreInputErrors) {
  EXPECT_THROW(load_run("/nonexistent/run"), InputError);
  const fs::path dir = fs::temp_directory_path() / "pllvo_report_empty";
  fs::remove_all(dir);
  fs::create_directories(dir);
  try {
    load_run(dir);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("trajectory.tum"), std::string::npos) << e.what();
  }
  io::write_tum(wavy_path(5), dir / "trajectory.tum");
  std::ofstream(dir / "stats.json") << "{ not json";
  EXPECT_THROW(load_run(dir), InputError);
}

TEST(RenderReport, PageHoldsEveryPlotAndTheFrameInline) {
  const auto gt = wavy_path(200);
  const auto dir = make_run_dir("render", gt);
  const std::string html = render_report(load_run(dir, dir / "groundtruth.tum"));
  size_t svgs = 0;
  for (size_t p = html.find("<svg"); p != std::string::npos; p = html.find("<svg", p + 1)) ++svgs;
  EXPECT_EQ(svgs, 2u + 1u + 3u + 3u + 1u);  // views, error, xyz, rpy, timing
  EXPECT_NE(html.find("data:image/png;base64,"), std::string::npos);
  EXPECT_EQ(html.find("http://"), html.find("http://www.w3.org/2000/svg"));  // no external resource
  EXPECT_EQ(html.find("<script"), std::string::npos);
}

TEST(RenderReport, TrajectoryPlotsShowThePlaneOfLargestMotion) {
  // A drive as KITTI's camera frame has it: forward along z, sideways along x, height (y) nearly constant.
  io::Trajectory drive;
  for (int i = 0; i < 100; ++i) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = Eigen::Vector3d(3.0 * std::sin(0.03 * i), 0.02 * std::sin(0.5 * i), 0.6 * i);
    drive.push_back(0.1 * i, T);
  }
  std::vector<Eigen::Vector3d> points;
  for (const auto& T : drive.poses) points.push_back(T.translation());
  EXPECT_EQ(axes_by_extent(points), (std::array<int, 3>{2, 0, 1}));
  const auto dir = make_run_dir("drive", drive);
  const std::string html = render_report(load_run(dir, dir / "groundtruth.tum"));
  EXPECT_NE(html.find("plane of largest motion (x-z)"), std::string::npos);
  EXPECT_NE(html.find("across it (y-z)"), std::string::npos);
  EXPECT_EQ(axes_by_extent({}), (std::array<int, 3>{0, 1, 2}));
}

// ---------------------------------------------------------------- headless Chromium

std::string find_chromium() {
  for (const char* p : {"/usr/bin/chromium", "/usr/bin/chromium-browser", "/usr/bin/google-chrome"})
    if (fs::exists(p)) return p;
  return {};
}

/// Rows of the image that contain pixels of `color` (BGR, +-tol), grouped into bands separated
/// by at least `gap` rows without any.
std::vector<std::pair<int, int>> color_bands(const cv::Mat& img, cv::Scalar color, int tol, int gap, int min_pixels,
                                             cv::Mat* mask_out = nullptr) {
  cv::Mat mask;
  cv::inRange(img, color - cv::Scalar(tol, tol, tol), color + cv::Scalar(tol, tol, tol), mask);
  if (mask_out) *mask_out = mask;
  std::vector<std::pair<int, int>> bands;
  int last = -gap - 1;
  for (int y = 0; y < mask.rows; ++y) {
    if (cv::countNonZero(mask.row(y)) < min_pixels) continue;
    if (y - last > gap) bands.push_back({y, y});
    bands.back().second = y;
    last = y;
  }
  return bands;
}

TEST(ReportScreenshot, HeadlessChromiumShowsThePlots) {
  const std::string chromium = find_chromium();
  if (chromium.empty()) GTEST_SKIP() << "chromium not installed (scripts/setup.sh installs it)";
  const auto gt = wavy_path(200);
  const auto dir = make_run_dir("screenshot", gt);
  const auto html = write_report(dir, dir / "report.html", dir / "groundtruth.tum");
  const auto png = dir / "screenshot.png";
  fs::remove(png);
  const std::string cmd = "timeout 120 " + chromium +
                          " --headless --no-sandbox --disable-gpu --hide-scrollbars --no-first-run"
                          " --user-data-dir=" + (dir / "chromium-profile").string() +
                          " --window-size=1240,2600 --screenshot=" + png.string() + " file://" + html.string() +
                          " > " + (dir / "chromium.log").string() + " 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << "chromium failed, see " << (dir / "chromium.log");
  const cv::Mat shot = cv::imread(png.string(), cv::IMREAD_COLOR);
  ASSERT_FALSE(shot.empty());
  ASSERT_EQ(shot.cols, 1240);

  // The estimate (#d62728, BGR 40,39,214) is drawn in four rows of plots: the two views, the
  // error over time, x/y/z and roll/pitch/yaw.
  cv::Mat red;
  const auto bands = color_bands(shot, cv::Scalar(40, 39, 214), 40, 25, 2, &red);
  ASSERT_GE(bands.size(), 4u) << "red bands: " << bands.size();
  // Both trajectory views have data: estimate pixels on the left and the right half of the first band.
  const cv::Mat first = red.rowRange(bands[0].first, bands[0].second + 1);
  EXPECT_GT(cv::countNonZero(first.colRange(0, 600)), 200);
  EXPECT_GT(cv::countNonZero(first.colRange(600, 1240)), 200);
  // Three plots side by side in the position and orientation rows: red in each third.
  for (size_t b = bands.size() - 2; b < bands.size(); ++b) {
    const cv::Mat row = red.rowRange(bands[b].first, bands[b].second + 1);
    for (int k = 0; k < 3; ++k) EXPECT_GT(cv::countNonZero(row.colRange(k * 400, k * 400 + 390)), 50) << "band " << b;
  }
  // Ground truth (#222222) is drawn too.
  cv::Mat dark;
  cv::inRange(shot, cv::Scalar(20, 20, 20), cv::Scalar(50, 50, 50), dark);
  EXPECT_GT(cv::countNonZero(dark), 2000);
  // Timing bars (#2171b5, BGR 181,113,33) below the plots.
  cv::Mat blue;
  const auto bars = color_bands(shot, cv::Scalar(181, 113, 33), 30, 3, 20, &blue);
  ASSERT_GE(bars.size(), 3u);  // three timers, three bars
  EXPECT_GT(bars.front().first, bands.back().second);
  // The embedded frame (magenta).
  cv::Mat magenta;
  cv::inRange(shot, cv::Scalar(235, 0, 235), cv::Scalar(255, 20, 255), magenta);
  EXPECT_GT(cv::countNonZero(magenta), 50000);
}

}  // namespace
}  // namespace pllvo::report
