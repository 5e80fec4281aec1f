// `pllvo run` on bad input: a clear message naming the problem, exit code 2, no crash and
// no half-written outputs. And on images with nothing to track: every frame processed.
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include "../support/cli_runner.h"

namespace fs = std::filesystem;
namespace {

using pllvo::test::CliResult;
using pllvo::test::run_cli;

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("pllvo_vo_cli_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

/// An image-folder dataset: camera.yaml (width x height, 20 fps) and `n` frames.
fs::path image_folder(const std::string& name, int n, cv::Size image_size, cv::Size calib_size,
                      bool blank = false) {
  const fs::path dir = fresh_dir(name);
  std::ofstream(dir / "camera.yaml") << "model: pinhole\nwidth: " << calib_size.width
                                     << "\nheight: " << calib_size.height
                                     << "\nfx: 300\nfy: 300\ncx: " << calib_size.width / 2.0
                                     << "\ncy: " << calib_size.height / 2.0
                                     << "\ndistortion_model: none\nfps: 20\n";
  fs::create_directories(dir / "images");
  cv::RNG rng(5);
  for (int i = 0; i < n; ++i) {
    cv::Mat img(image_size, CV_8UC1, cv::Scalar(0));
    if (!blank) {
      rng.fill(img, cv::RNG::UNIFORM, 0, 255);
      cv::GaussianBlur(img, img, cv::Size(0, 0), 2.0);
    }
    char file[32];
    std::snprintf(file, sizeof file, "%06d.png", i);
    cv::imwrite((dir / "images" / file).string(), img);
  }
  return dir;
}

void expect_no_outputs(const fs::path& out) {
  for (const char* f : {"trajectory.tum", "keyframes.tum", "stats.json", "map.ply"})
    EXPECT_FALSE(fs::exists(out / f)) << f << " written despite the error";
}

TEST(RunCli, MissingFolderIsAClearError) {
  const fs::path out = fresh_dir("missing_out");
  const auto r = run_cli("run /nonexistent/pllvo/dataset --out " + out.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("pllvo: error:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("/nonexistent/pllvo/dataset"), std::string::npos) << r.output;
  expect_no_outputs(out);
}

TEST(RunCli, UnreadableImageNamesTheFile) {
  const fs::path data = image_folder("unreadable", 6, {160, 120}, {160, 120});
  std::ofstream(data / "images" / "000003.png", std::ios::trunc) << "this is not a png";
  const fs::path out = fresh_dir("unreadable_out");
  const auto r = run_cli("run " + data.string() + " --out " + out.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("pllvo: error:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("000003.png"), std::string::npos) << r.output;
  expect_no_outputs(out);
}

TEST(RunCli, CalibrationMismatchIsAClearError) {
  const fs::path data = image_folder("mismatch", 4, {160, 120}, {320, 240});
  const fs::path out = fresh_dir("mismatch_out");
  const auto r = run_cli("run " + data.string() + " --out " + out.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("pllvo: error:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("160"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("320"), std::string::npos) << r.output;
  expect_no_outputs(out);
}

TEST(RunCli, BadConfigNamesTheKey) {
  const fs::path data = image_folder("badconfig", 3, {160, 120}, {160, 120});
  std::ofstream(data / "vo.yaml") << "keyframes:\n  max_intervall_s: 2\n";
  const fs::path out = fresh_dir("badconfig_out");
  const auto r = run_cli("run " + data.string() + " --out " + out.string() + " --config " + (data / "vo.yaml").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("keyframes.max_intervall_s"), std::string::npos) << r.output;
  expect_no_outputs(out);
}

TEST(RunCli, BlankFramesAreProcessedWithoutCrashing) {
  const fs::path data = image_folder("blank", 8, {160, 120}, {160, 120}, true);
  const fs::path out = fresh_dir("blank_out");
  const auto r = run_cli("run " + data.string() + " --out " + out.string() + " --single-thread");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("tracked 0 of 8 frames"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("not tracked: frames 0-7"), std::string::npos) << r.output;
  EXPECT_TRUE(fs::exists(out / "stats.json"));
  EXPECT_TRUE(fs::exists(out / "trajectory.tum"));
  EXPECT_EQ(fs::file_size(out / "trajectory.tum"), 0u);
}

}  // namespace
