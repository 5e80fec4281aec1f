#include <gtest/gtest.h>

#include <cmath>

#include <opencv2/imgcodecs.hpp>

#include "dataset_test_utils.h"
#include "pllvo/io/folder_sequence.h"
#include "pllvo/io/sequence.h"

using namespace pllvo::io;
using namespace pllvo::io::testing;

TEST(FolderSequence, LoadsEventCameraDatasetFolder) {
  const auto seq = open_sequence(data_path("ecd_slider_hdr_close_149"));
  EXPECT_EQ(seq->format(), "folder");
  ASSERT_EQ(seq->size(), 149u);
  const auto& calib = seq->calibration();
  EXPECT_FALSE(calib.stereo());
  EXPECT_EQ(calib.rate_hz, 22.69);
  const auto& cam = *calib.cam0;
  EXPECT_EQ(cam.name(), "pinhole-radtan");
  EXPECT_EQ(cam.width(), 240);
  EXPECT_EQ(cam.height(), 180);
  EXPECT_EQ(cam.intrinsics().fx, 335.419462958);
  EXPECT_EQ(cam.intrinsics().fy, 335.352935612);
  EXPECT_EQ(cam.intrinsics().cx, 129.924663379);
  EXPECT_EQ(cam.intrinsics().cy, 99.1864303447);
  EXPECT_EQ(cam.distortion(),
            (std::vector<double>{-0.138592767408, 0.0933736664192, -0.000335586987532, 0.000173720158228, 0.0}));
  EXPECT_EQ(seq->timestamp(0), 0.001270000);
  EXPECT_EQ(seq->timestamp(148), 6.522943999);
  EXPECT_EQ(seq->image_path(148).filename(), "frame_00000148.png");
}

TEST(FolderSequence, GroundTruthIsTheSliderTranslation) {
  const auto seq = open_sequence(data_path("ecd_slider_hdr_close_149"));
  ASSERT_TRUE(seq->ground_truth().has_value());
  const auto& gt = *seq->ground_truth();
  ASSERT_EQ(gt.size(), 654u);
  EXPECT_EQ(gt.stamps.front(), 0.012753562);
  EXPECT_EQ(gt.stamps.back(), 6.542148406);
  EXPECT_EQ(gt.poses.front().translation(), Eigen::Vector3d(0.100087239583, 0, 0));
  EXPECT_TRUE(gt.poses.back().linear().isIdentity(0));
  EXPECT_NEAR(gt.poses.back().translation().x() - gt.poses.front().translation().x(), 1.0, 0.01);
}

TEST(FolderSequence, FramesAreTheRightGrayImages) {
  const auto seq = open_sequence(data_path("ecd_slider_hdr_close_149"));
  const Frame f60 = seq->frame(60);
  ASSERT_EQ(f60.left.type(), CV_8UC1);
  EXPECT_EQ(f60.left.size(), cv::Size(240, 180));
  EXPECT_EQ(pixel_sum(f60.left), 2643809.0);  // independent PNG decode; README: mean 61 at frame 60
  EXPECT_NEAR(cv::mean(f60.left)[0], 61.2, 0.05);
  EXPECT_EQ(pixel_sum(seq->frame(0).left), 13942.0);  // nearly black (HDR start)
}

TEST(FolderSequence, WithoutImagesTxtFramesAreSortedByNameAndTimedByFps) {
  TempDir tmp;
  const auto src = data_path("ecd_slider_hdr_close_149");
  copy_into(src / "camera.yaml", tmp / "camera.yaml");
  for (const auto* name : {"frame_00000062.png", "frame_00000060.png", "frame_00000061.png"})
    copy_into(src / "images" / name, tmp / "images" / name);
  const auto seq = open_sequence(tmp.path());
  EXPECT_EQ(seq->format(), "folder");
  ASSERT_EQ(seq->size(), 3u);
  EXPECT_EQ(seq->image_path(0).filename(), "frame_00000060.png");
  EXPECT_EQ(seq->image_path(2).filename(), "frame_00000062.png");
  EXPECT_EQ(seq->timestamp(0), 0.0);
  EXPECT_EQ(seq->timestamp(2), 2.0 / 22.69);
  EXPECT_EQ(pixel_sum(seq->frame(0).left), 2643809.0);
  EXPECT_FALSE(seq->ground_truth().has_value());

  // The images may also sit in the folder itself, next to camera.yaml.
  fs::rename(tmp / "images" / "frame_00000061.png", tmp / "frame_00000061.png");
  fs::remove_all(tmp / "images");
  EXPECT_EQ(open_sequence(tmp.path())->size(), 1u);
}

TEST(FolderSequence, WithoutImagesTxtFpsIsRequired) {
  TempDir tmp;
  write_file(tmp / "camera.yaml", "width: 240\nheight: 180\nfx: 300\nfy: 300\ncx: 120\ncy: 90\n");
  copy_into(data_path("ecd_slider_hdr_close_149/images/frame_00000060.png"), tmp / "images" / "a.png");
  const auto e = expect_input_error([&] { FolderSequence seq(tmp.path()); });
  EXPECT_EQ(e.file(), (tmp / "camera.yaml").string());
  EXPECT_EQ(e.key(), "fps");
}

TEST(FolderSequence, DepthFolderGivesEachImageItsDepthInMetres) {
  TempDir tmp;
  const auto src = data_path("ecd_slider_hdr_close_149");
  write_file(tmp / "camera.yaml", "width: 240\nheight: 180\nfx: 300\nfy: 300\ncx: 120\ncy: 90\nfps: 20\n");
  for (const auto* name : {"frame_00000060.png", "frame_00000061.png"})
    copy_into(src / "images" / name, tmp / "images" / name);
  fs::create_directories(tmp / "depth");
  for (const auto* name : {"frame_00000060.png", "frame_00000061.png"})
    cv::imwrite((tmp / "depth" / name).string(), cv::Mat(180, 240, CV_16UC1, cv::Scalar(1500)));
  // Without depth_factor the 16-bit values have no unit.
  auto e = expect_input_error([&] { open_sequence(tmp.path()); });
  EXPECT_EQ(e.file(), (tmp / "camera.yaml").string());
  EXPECT_EQ(e.key(), "depth_factor");

  write_file(tmp / "camera.yaml", "width: 240\nheight: 180\nfx: 300\nfy: 300\ncx: 120\ncy: 90\nfps: 20\n"
                                  "depth_factor: 1000\n");
  const auto seq = open_sequence(tmp.path());
  ASSERT_TRUE(seq->calibration().has_depth());
  const Frame f = seq->frame(1);
  ASSERT_EQ(f.depth.type(), CV_32FC1);
  EXPECT_FLOAT_EQ(f.depth.at<float>(90, 120), 1.5f);

  fs::remove(tmp / "depth" / "frame_00000061.png");
  e = expect_input_error([&] { open_sequence(tmp.path()); });
  EXPECT_EQ(e.file(), (tmp / "depth" / "frame_00000061.png").string());
}
