// `pllvo bench`, `pllvo report` and `pllvo run --report/--view` through the built CLI: bad input
// is one clear message and exit code 2; a short synthetic sequence gives a full table and page.
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <unistd.h>
#include <nlohmann/json.hpp>
#include "../support/cli_runner.h"

namespace fs = std::filesystem;
namespace {

using pllvo::test::CliResult;
using pllvo::test::run_cli;

// Per process: CTest runs these tests in parallel processes.
const fs::path kRoot = fs::temp_directory_path() / ("pllvo_report_cli_" + std::to_string(::getpid()));
const std::string kMethods = std::string(" --methods-file ") + PLLVO_SOURCE_DIR + "/config/bench.yaml";

TEST(BenchCli, BadInputIsOneMessageAndExitCode2) {
  auto r = run_cli("bench" + kMethods);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("pllvo: error:"), std::string::npos) << r.output;

  r = run_cli("bench /nonexistent/dataset" + kMethods);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("/nonexistent/dataset"), std::string::npos) << r.output;

  r = run_cli("bench --synth-suite " + (kRoot / "suite").string() + " --synth-presets no_such_preset" + kMethods);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("no_such_preset"), std::string::npos) << r.output;

  r = run_cli("bench " + std::string(PLLVO_SOURCE_DIR) + " --methods orb,nope" + kMethods);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("nope"), std::string::npos) << r.output;

  r = run_cli("bench " + std::string(PLLVO_SOURCE_DIR) + " --set frontend.colour=red" + kMethods);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("frontend.colour"), std::string::npos) << r.output;

  r = run_cli("bench . --methods-file /nonexistent/bench.yaml");
  EXPECT_EQ(r.exit_code, 2) << r.output;
}

TEST(ReportCli, MissingRunFolderIsExitCode2) {
  const auto r = run_cli("report /nonexistent/run");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("/nonexistent/run"), std::string::npos) << r.output;
}

/// One short stereo synthetic sequence (2 s, 41 frames) for the end-to-end tests below.
class SyntheticRun : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (fs::exists(sequence() / "mav0")) return;
    fs::remove_all(kRoot / "suite");
    const auto r = run_cli("synth --preset easy_normal --stereo --duration 2 --out " + sequence().string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  static fs::path sequence() { return kRoot / "suite" / "easy_normal"; }
};

TEST_F(SyntheticRun, BenchPrintsTheTableAndWritesJsonAndCsv) {
  const fs::path out = kRoot / "bench_out";
  fs::remove_all(out);
  const auto r = run_cli("bench --synth-suite " + (kRoot / "suite").string() +
                         " --synth-presets easy_normal --methods orb,klt --repeat 2 --single-thread --out " +
                         out.string() + kMethods);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("easy_normal  orb"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("easy_normal  klt"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("[4/4"), std::string::npos) << r.output;  // progress
  std::ifstream f(out / "bench.json");
  const auto j = nlohmann::json::parse(f);
  ASSERT_EQ(j["cells"].size(), 2u);
  for (const auto& c : j["cells"]) {
    EXPECT_EQ(c["runs"].size(), 2u);
    EXPECT_EQ(c["failed"], 0);
    // Stereo, 2 s of easy motion: tracked throughout, ATE of a few centimetres at most.
    EXPECT_DOUBLE_EQ(c["median"]["tracked_share"].get<double>(), 1.0) << c.dump();
    EXPECT_LT(c["median"]["ate_rmse_m"].get<double>(), 0.05) << c.dump();
    // Single-thread runs are deterministic: no spread in accuracy.
    EXPECT_DOUBLE_EQ(c["spread"]["ate_rmse_m"].get<double>(), 0.0);
  }
  EXPECT_NEAR(j["cells"][0]["median"]["speed_ratio"].get<double>(), 1.0, 1e-9);  // orb against itself
  EXPECT_TRUE(fs::exists(out / "bench.csv"));
}

TEST_F(SyntheticRun, RunWithReportWritesThePageWithFrames) {
  const fs::path out = kRoot / "run_report";
  fs::remove_all(out);
  const auto r = run_cli("run " + sequence().string() + " --out " + out.string() + " --report --report-frames 3");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ASSERT_TRUE(fs::exists(out / "report.html"));
  size_t frames = 0;
  for (const auto& e : fs::directory_iterator(out / "frames")) frames += e.path().extension() == ".png";
  EXPECT_EQ(frames, 3u);
  std::stringstream html;
  html << std::ifstream(out / "report.html").rdbuf();
  EXPECT_NE(html.str().find("ground truth"), std::string::npos);  // found via stats.json
  EXPECT_EQ(html.str().find("class=\"note\""), std::string::npos) << "unexpected note";
  // `pllvo report` on the same folder writes the page again.
  const auto again = run_cli("report " + out.string() + " --out " + (out / "again.html").string());
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_TRUE(fs::exists(out / "again.html"));
}

TEST_F(SyntheticRun, ViewNeedsADisplayAndFailsCleanlyWithoutOne) {
  const fs::path out = kRoot / "run_view";
  fs::remove_all(out);
  auto r = run_cli("run " + sequence().string() + " --out " + out.string() + " --view",
                   "env -u DISPLAY -u WAYLAND_DISPLAY -u QT_QPA_PLATFORM");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--view needs a display"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(out / "trajectory.tum"));
  // With Qt's offscreen platform the window works without a screen.
  r = run_cli("run " + sequence().string() + " --out " + out.string() + " --view --max-frames 10",
              "env QT_QPA_PLATFORM=offscreen");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(out / "trajectory.tum"));
}

}  // namespace
