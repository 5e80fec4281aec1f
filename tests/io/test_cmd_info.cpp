// `pllvo info`, run as the built binary.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <string>

#include "dataset_test_utils.h"
#include "../support/cli_runner.h"

using namespace pllvo::io::testing;

namespace {

using pllvo::test::run_cli;

bool has_line(const std::string& out, const std::string& name, const std::string& value_start) {
  for (size_t pos = 0; (pos = out.find(name, pos)) != std::string::npos; ++pos) {
    if (pos != 0 && out[pos - 1] != '\n') continue;
    const size_t v = out.find_first_not_of(' ', pos + name.size());
    if (out.compare(v, value_start.size(), value_start) == 0) return true;
  }
  return false;
}

}  // namespace

TEST(CmdInfo, DescribesTheEurocFixture) {
  const auto r = run_cli("info '" + data_path("euroc_V1_01_easy_micro").string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has_line(r.output, "format", "euroc (stereo)")) << r.output;
  EXPECT_TRUE(has_line(r.output, "frames", "74\n")) << r.output;
  EXPECT_TRUE(has_line(r.output, "duration", "3.650 s")) << r.output;
  EXPECT_TRUE(has_line(r.output, "rate", "20 Hz")) << r.output;
  EXPECT_TRUE(has_line(r.output, "resolution", "752 x 480")) << r.output;
  EXPECT_TRUE(has_line(r.output, "cam0", "pinhole-radtan  fx 458.654  fy 457.296  cx 367.215  cy 248.375")) << r.output;
  EXPECT_TRUE(has_line(r.output, "baseline", "0.1100")) << r.output;
  EXPECT_TRUE(has_line(r.output, "ground truth", "733 poses")) << r.output;
}

TEST(CmdInfo, MonoAndCameraYamlOptions) {
  auto r = run_cli("info --mono '" + data_path("euroc_V1_01_easy_micro").string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has_line(r.output, "format", "euroc (mono)")) << r.output;
  EXPECT_EQ(r.output.find("baseline"), std::string::npos) << r.output;

  TempDir tmp;
  write_file(tmp / "cam.yaml", "width: 640\nheight: 480\nfx: 500\nfy: 501\ncx: 320\ncy: 240\n");
  r = run_cli("info --format tum --camera-yaml '" + (tmp / "cam.yaml").string() + "' '" +
              data_path("tum_fr3_office_snippet").string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has_line(r.output, "cam0", "pinhole-radtan  fx 500  fy 501")) << r.output;
  EXPECT_TRUE(has_line(r.output, "frames", "16\n")) << r.output;
  // depth.txt pairs a depth image with each of the 16 colour frames (all within 20 ms), and a
  // camera YAML without depth_factor takes TUM's 5000.
  EXPECT_TRUE(has_line(r.output, "format", "tum (mono, depth: RGB-D)")) << r.output;
  EXPECT_TRUE(has_line(r.output, "depth", "16 of 16 frames, metres = value / 5000")) << r.output;
}

TEST(CmdInfo, MissingFolderExitsWithTwoAndNamesIt) {
  TempDir tmp;
  const auto missing = (tmp / "no_such_dataset").string();
  const auto r = run_cli("info '" + missing + "'");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("pllvo: error: " + missing), std::string::npos) << r.output;
}
