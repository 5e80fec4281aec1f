// `pllvo demo` end to end through the command line: renders a short sequence, runs the
// odometry and prints ATE, frames per second and the per-module split; with no SuperPoint
// weights it runs ORB and says so.
#include <array>
#include <cstdio>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "../support/cli_runner.h"
#include "pllvo/vo/point_frontend.h"

namespace fs = std::filesystem;
namespace {

using pllvo::test::CliResult;
using pllvo::test::run_cli;

TEST(DemoCli, RendersRunsAndReportsAteAndSpeed) {
  const fs::path out = fs::temp_directory_path() / "pllvo_vo_demo_cli";
  fs::remove_all(out);
  const CliResult r = run_cli("demo --duration 3 --single-thread --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("ATE RMSE"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("% of the"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("frames/s"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("point tracking (KLT)"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("point extraction"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("bundle adjustment"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("61/61 frames tracked"), std::string::npos) << r.output;
  // The front end "auto" chose, and the notice when it is the ORB fallback.
  std::string notice;
  pllvo::vo::FrontendConfig automatic;
  automatic.type = "auto";
  const std::string frontend = pllvo::vo::resolve_frontend_type(automatic, &notice);
  EXPECT_NE(r.output.find(frontend + " front end"), std::string::npos) << r.output;
  if (frontend == "orb") EXPECT_NE(r.output.find("notice: no SuperPoint weights"), std::string::npos) << r.output;
  EXPECT_TRUE(fs::exists(out / "sequence" / "mav0" / "cam1" / "data.csv"));
  EXPECT_TRUE(fs::exists(out / "run" / "trajectory.tum"));
  EXPECT_TRUE(fs::exists(out / "run" / "stats.json"));
  // The sequence is not overwritten by a second run.
  const CliResult again = run_cli("demo --duration 3 --out " + out.string());
  EXPECT_EQ(again.exit_code, 2) << again.output;
  EXPECT_NE(again.output.find("already exists"), std::string::npos) << again.output;
  fs::remove_all(out);
}

TEST(DemoCli, AConfiguredWeightsPathThatDoesNotExistIsAnError) {
  // Only an unconfigured lookup that finds nothing falls back to ORB (checked above when no
  // weights are installed); a configured path must exist, never a silent fallback.
  const fs::path empty = fs::temp_directory_path() / "pllvo_vo_demo_no_models";
  fs::create_directories(empty);
  pllvo::vo::FrontendConfig c;
  c.type = "auto";
  c.superpoint_weights = (empty / "missing.safetensors").string();
  std::string notice;
  EXPECT_THROW(pllvo::vo::resolve_frontend_type(c, &notice), std::exception);
}

}  // namespace
