#include <gtest/gtest.h>

#include "dataset_test_utils.h"
#include "pllvo/io/kitti_sequence.h"
#include "pllvo/io/sequence.h"

using namespace pllvo::io;
using namespace pllvo::io::testing;

namespace {

/// sequences/<id>/ with image_0 (and image_1 holding the same images) for `frames` frames,
/// calib.txt and times.txt from the fixture.
fs::path make_kitti_copy(const fs::path& root, const std::string& id, size_t frames, bool stereo) {
  const auto src = data_path("kitti_04_mono51/sequences/04");
  const auto seq = root / "sequences" / id;
  copy_into(src / "calib.txt", seq / "calib.txt");
  const auto times = read_lines(src / "times.txt");
  write_lines(seq / "times.txt", {times.begin(), times.begin() + frames});
  char name[16];
  for (size_t i = 0; i < frames; ++i) {
    std::snprintf(name, sizeof name, "%06zu.png", i);
    copy_into(src / "image_0" / name, seq / "image_0" / name);
    if (stereo) copy_into(src / "image_0" / name, seq / "image_1" / name);
  }
  return seq;
}

}  // namespace

TEST(KittiSequence, LoadsFixtureFromRootAndFromSequenceFolder) {
  for (const auto* path : {"kitti_04_mono51", "kitti_04_mono51/sequences/04", "kitti_04_mono51/sequences/04/"}) {
    SCOPED_TRACE(path);
    const auto seq = open_sequence(data_path(path));
    EXPECT_EQ(seq->format(), "kitti");
    ASSERT_EQ(seq->size(), 51u);
    const auto& calib = seq->calibration();
    EXPECT_FALSE(calib.stereo());  // the fixture has no image_1/
    const auto& cam = *calib.cam0;
    EXPECT_EQ(cam.width(), 1226);
    EXPECT_EQ(cam.height(), 370);
    EXPECT_EQ(cam.intrinsics().fx, 707.0912);
    EXPECT_EQ(cam.intrinsics().fy, 707.0912);
    EXPECT_EQ(cam.intrinsics().cx, 601.8873);
    EXPECT_EQ(cam.intrinsics().cy, 183.1104);
    for (double d : cam.distortion()) EXPECT_EQ(d, 0.0);
    EXPECT_EQ(seq->timestamp(0), 0.0);
    EXPECT_EQ(seq->timestamp(50), 5.0);
    EXPECT_NEAR(calib.rate_hz, 10.0, 1e-12);
    ASSERT_TRUE(seq->ground_truth().has_value());  // poses/04.txt found from any spelling
    EXPECT_EQ(seq->ground_truth()->size(), 51u);
  }
}

TEST(KittiSequence, GroundTruthIsOnePosePerFrame) {
  const auto seq = open_sequence(data_path("kitti_04_mono51"));
  ASSERT_TRUE(seq->ground_truth().has_value());
  const auto& gt = *seq->ground_truth();
  ASSERT_EQ(gt.size(), 51u);
  ASSERT_TRUE(gt.has_stamps());
  EXPECT_EQ(gt.stamps[1], 0.1);
  // Line 2: 9.999995e-01 7.196824e-04 -6.870876e-04 -1.401751e-02 ... 1.198998e+00
  EXPECT_EQ(gt.poses[1].translation(), Eigen::Vector3d(-1.401751e-02, -2.820321e-02, 1.198998e+00));
  EXPECT_EQ(gt.poses[1].linear()(0, 1), 7.196824e-04);
  EXPECT_LT(gt.poses[0].translation().norm(), 1e-15);
  // README: a straight drive of 59.9 m over the 51 frames.
  EXPECT_NEAR((gt.poses[50].translation() - gt.poses[0].translation()).norm(), 59.9, 0.5);
}

TEST(KittiSequence, FramesAreTheRightGrayImages) {
  const auto seq = open_sequence(data_path("kitti_04_mono51"));
  const Frame f = seq->frame(50);
  ASSERT_EQ(f.left.type(), CV_8UC1);
  EXPECT_EQ(f.left.size(), cv::Size(1226, 370));
  EXPECT_EQ(pixel_sum(f.left), 41815371.0);  // independent PNG decode
  EXPECT_EQ(f.left.at<uint8_t>(20, 10), 132);
  EXPECT_EQ(f.timestamp, 5.0);
}

TEST(KittiSequence, CalibrationGivesBaselineFromP1) {
  const auto calib = read_kitti_calib(data_path("kitti_04_mono51/sequences/04/calib.txt"));
  EXPECT_EQ(calib.cam0.fx, 707.0912);
  ASSERT_TRUE(calib.cam1.has_value());
  EXPECT_EQ(calib.cam1->cx, 601.8873);
  EXPECT_NEAR(calib.baseline, 379.8145 / 707.0912, 1e-15);
  EXPECT_NEAR(calib.baseline, 0.5372, 1e-4);
}

TEST(KittiSequence, StereoWhenImage1Exists) {
  TempDir tmp;
  make_kitti_copy(tmp.path(), "04", 3, true);
  const auto seq = open_sequence(tmp.path());
  ASSERT_EQ(seq->size(), 3u);
  const auto& calib = seq->calibration();
  ASSERT_TRUE(calib.stereo());
  EXPECT_NEAR(calib.baseline(), 379.8145 / 707.0912, 1e-12);
  EXPECT_NEAR(calib.T_body_cam1.translation().x(), 379.8145 / 707.0912, 1e-12);
  EXPECT_TRUE(calib.T_body_cam0.isApprox(Eigen::Isometry3d::Identity()));
  EXPECT_EQ(calib.cam1->intrinsics().fx, 707.0912);
  const Frame f = seq->frame(2);
  EXPECT_EQ(f.right.size(), cv::Size(1226, 370));
  EXPECT_EQ(pixel_sum(f.right), pixel_sum(f.left));
  EXPECT_FALSE(seq->ground_truth().has_value());  // no poses/04.txt in the copy

  SequenceOptions mono;
  mono.mono = true;
  EXPECT_FALSE(open_sequence(tmp.path(), mono)->calibration().stereo());
}

TEST(KittiSequence, RootWithSeveralSequencesAsksForOne) {
  TempDir tmp;
  make_kitti_copy(tmp.path(), "00", 2, false);
  make_kitti_copy(tmp.path(), "04", 2, false);
  const auto e = expect_input_error([&] { open_sequence(tmp.path()); });
  EXPECT_EQ(e.file(), (tmp / "sequences").string());
  EXPECT_NE(std::string(e.what()).find("00, 04"), std::string::npos) << e.what();
  EXPECT_EQ(open_sequence(tmp / "sequences" / "00")->size(), 2u);
}

TEST(KittiSequence, PoseCountMustMatchFrames) {
  TempDir tmp;
  make_kitti_copy(tmp.path(), "04", 3, false);
  const auto poses = read_lines(data_path("kitti_04_mono51/poses/04.txt"));
  write_lines(tmp / "poses" / "04.txt", {poses.begin(), poses.begin() + 4});
  const auto e = expect_input_error([&] { open_sequence(tmp.path()); });
  EXPECT_EQ(e.file(), (tmp / "poses" / "04.txt").string());
  write_lines(tmp / "poses" / "04.txt", {poses.begin(), poses.begin() + 3});
  EXPECT_EQ(open_sequence(tmp.path())->ground_truth()->size(), 3u);
}

TEST(KittiSequence, CalibWithoutP0NamesTheKey) {
  TempDir tmp;
  write_file(tmp / "calib.txt", "P1: 1 0 0 0 0 1 0 0 0 0 1 0\n");
  const auto e = expect_input_error([&] { read_kitti_calib(tmp / "calib.txt"); });
  EXPECT_EQ(e.key(), "P0");
  write_file(tmp / "calib.txt", "P0: 700 0 600 0 0 700 180 0 0 0 1 0\nP1: 700 0 600 -380 0 700 180 0\n");
  EXPECT_EQ(expect_input_error([&] { read_kitti_calib(tmp / "calib.txt"); }).line(), 2);
}
