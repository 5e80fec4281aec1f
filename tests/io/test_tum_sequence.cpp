#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "dataset_test_utils.h"
#include "pllvo/io/sequence.h"
#include "pllvo/io/tum_sequence.h"

using namespace pllvo::io;
using namespace pllvo::io::testing;

TEST(TumSequence, LoadsFixtureWithCameraYaml) {
  const auto seq = open_sequence(data_path("tum_fr3_office_snippet"));
  EXPECT_EQ(seq->format(), "tum");
  ASSERT_EQ(seq->size(), 16u);
  const auto& calib = seq->calibration();
  EXPECT_FALSE(calib.stereo());
  EXPECT_EQ(calib.rate_hz, 30.0);  // camera.yaml's fps
  const auto& cam = *calib.cam0;
  EXPECT_EQ(cam.width(), 640);
  EXPECT_EQ(cam.height(), 480);
  EXPECT_EQ(cam.intrinsics().fx, 535.4);
  EXPECT_EQ(cam.intrinsics().fy, 539.2);
  EXPECT_EQ(cam.intrinsics().cx, 320.1);
  EXPECT_EQ(cam.intrinsics().cy, 247.6);
  for (double d : cam.distortion()) EXPECT_EQ(d, 0.0);
  EXPECT_EQ(seq->timestamp(0), 1341847980.722988);
  EXPECT_EQ(seq->timestamp(15), 1341847981.222978);
  EXPECT_EQ(seq->image_path(3).filename(), "1341847980.822978.png");
}

TEST(TumSequence, GroundTruthIsTheTumFileAsIs) {
  const auto seq = open_sequence(data_path("tum_fr3_office_snippet"));
  ASSERT_TRUE(seq->ground_truth().has_value());
  const auto& gt = *seq->ground_truth();
  ASSERT_EQ(gt.size(), 144u);
  EXPECT_EQ(gt.stamps.front(), 1341847980.79);
  EXPECT_EQ(gt.stamps.back(), 1341847982.22);
  // 1341847980.7900 -0.6832 2.6909 1.7373 0.0003 0.8617 -0.5072 -0.0145 (qx qy qz qw)
  EXPECT_LT((gt.poses[0].translation() - Eigen::Vector3d(-0.6832, 2.6909, 1.7373)).norm(), 1e-12);
  const Eigen::Matrix3d R = Eigen::Quaterniond(-0.0145, 0.0003, 0.8617, -0.5072).normalized().toRotationMatrix();
  EXPECT_LT((gt.poses[0].linear() - R).norm(), 1e-12);
}

TEST(TumSequence, ColourFramesComeBackGray) {
  const auto seq = open_sequence(data_path("tum_fr3_office_snippet"));
  const Frame f = seq->frame(0);
  ASSERT_EQ(f.left.type(), CV_8UC1);
  EXPECT_EQ(f.left.size(), cv::Size(640, 480));
  EXPECT_TRUE(f.right.empty());
  // Independent decode of the RGB PNG with Y = 0.299 R + 0.587 G + 0.114 B (fixed-point
  // rounding may differ by 1 per pixel); swapping R and B would give mean 108.58.
  EXPECT_NEAR(cv::mean(f.left)[0], 111.3846, 0.01);
  EXPECT_EQ(f.left.at<uint8_t>(20, 10), 155);
  EXPECT_NEAR(f.left.at<uint8_t>(213, 316), 192, 1);  // RGB (250, 197, 16): strongly coloured
  EXPECT_NEAR(cv::mean(seq->frame(15).left)[0], 34348404.0 / (640 * 480), 0.01);
}

TEST(TumSequence, CameraYamlOptionOverridesTheDefault) {
  TempDir tmp;
  write_file(tmp / "other.yaml",
             "model: pinhole\nwidth: 640\nheight: 480\nfx: 517.3\nfy: 516.5\ncx: 318.6\ncy: 255.3\n"
             "distortion_model: radtan\ndistortion: [0.2624, -0.9531, -0.0054, 0.0026, 1.1633]\n");
  SequenceOptions options;
  options.camera_yaml = tmp / "other.yaml";
  const auto seq = open_sequence(data_path("tum_fr3_office_snippet"), options);
  EXPECT_EQ(seq->calibration().cam0->intrinsics().fx, 517.3);
  EXPECT_EQ(seq->calibration().cam0->distortion()[4], 1.1633);
  EXPECT_NEAR(seq->calibration().rate_hz, 15.0 / 0.49999, 1e-3);  // no fps: measured mean rate
}

TEST(TumSequence, MissingCameraYamlIsNamed) {
  TempDir tmp;
  copy_into(data_path("tum_fr3_office_snippet/rgb.txt"), tmp / "rgb.txt");
  const auto e = expect_input_error([&] { TumSequence seq(tmp.path()); });
  EXPECT_EQ(e.file(), (tmp / "camera.yaml").string());
  EXPECT_NE(std::string(e.what()).find("--camera-yaml"), std::string::npos) << e.what();
}

TEST(TumSequence, EachColourFrameTakesTheNearestDepthImageInMetres) {
  const auto seq = open_sequence(data_path("tum_fr3_office_snippet"));
  const auto& calib = seq->calibration();
  ASSERT_TRUE(calib.has_depth());
  EXPECT_EQ(calib.depth_factor, 5000.0);  // camera.yaml's depth_factor (TUM's)
  ASSERT_EQ(seq->depth_files().size(), 16u);
  // rgb 1341847980.822978 and depth 1341847980.822989 are 11 us apart.
  EXPECT_EQ(seq->depth_files()[3].filename(), "1341847980.822989.png");
  EXPECT_EQ(seq->depth_files()[15].filename(), "1341847981.222989.png");
  const Frame f = seq->frame(3);
  ASSERT_EQ(f.depth.type(), CV_32FC1);
  EXPECT_EQ(f.depth.size(), cv::Size(640, 480));
  // The raw 16-bit value there is 10920 (read independently with Python's OpenCV): 2.184 m.
  EXPECT_FLOAT_EQ(f.depth.at<float>(240, 320), 10920.0f / 5000.0f);
  EXPECT_NEAR(cv::countNonZero(f.depth) / (640.0 * 480.0), 0.8288, 1e-3);  // 17 % of pixels have no depth
}

TEST(TumSequence, MonoOrNoDepthOptionLeavesTheDepthImagesOut) {
  SequenceOptions mono;
  mono.mono = true;
  SequenceOptions no_depth;
  no_depth.depth = false;
  for (const auto& options : {mono, no_depth}) {
    const auto seq = open_sequence(data_path("tum_fr3_office_snippet"), options);
    EXPECT_FALSE(seq->calibration().has_depth());
    EXPECT_TRUE(seq->depth_files().empty());
    EXPECT_TRUE(seq->frame(3).depth.empty());
  }
}

TEST(TumSequence, FramesWithoutADepthImageNearInTimeHaveNone) {
  SequenceOptions options;
  options.depth_max_dt = 5e-6;  // the nearest depth image of each colour frame is 9-71 us away
  const auto seq = open_sequence(data_path("tum_fr3_office_snippet"), options);
  ASSERT_TRUE(seq->calibration().has_depth());
  for (size_t i = 0; i < seq->size(); ++i) EXPECT_TRUE(seq->depth_files()[i].empty()) << i;
  EXPECT_TRUE(seq->frame(3).depth.empty());
  options.depth_max_dt = 2e-5;  // 20 us: frame 3 (11.0 us) has one, frame 0 (32.2 us) none
  const auto near = open_sequence(data_path("tum_fr3_office_snippet"), options);
  EXPECT_TRUE(near->depth_files()[0].empty());
  EXPECT_FALSE(near->depth_files()[3].empty());
}

TEST(TumSequence, AnEightBitDepthImageIsRefusedWithItsName) {
  TempDir tmp;
  const auto root = data_path("tum_fr3_office_snippet");
  copy_into(root / "camera.yaml", tmp / "camera.yaml");
  write_file(tmp / "rgb.txt", "1.0 " + (root / "rgb/1341847980.822978.png").string() + "\n");
  cv::imwrite((tmp / "d.png").string(), cv::Mat(480, 640, CV_8UC1, cv::Scalar(7)));
  write_file(tmp / "depth.txt", "1.001 d.png\n");
  const auto seq = open_sequence(tmp.path());
  const auto e = expect_input_error([&] { seq->frame(0); });
  EXPECT_EQ(e.file(), (tmp / "d.png").string());
  EXPECT_NE(std::string(e.what()).find("16-bit"), std::string::npos) << e.what();
}
