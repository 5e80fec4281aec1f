#include <gtest/gtest.h>

#include "dataset_test_utils.h"
#include "pllvo/camera/stereo_rectifier.h"
#include "pllvo/io/euroc_sequence.h"
#include "pllvo/io/sequence.h"

using namespace pllvo::io;
using namespace pllvo::io::testing;

namespace {

// mav0/cam0/sensor.yaml and cam1/sensor.yaml of V1_01_easy.
const double kT_BS_cam0[16] = {0.0148655429818, -0.999880929698, 0.00414029679422, -0.0216401454975,
                               0.999557249008,  0.0149672133247, 0.025715529948,   -0.064676986768,
                               -0.0257744366974, 0.00375618835797, 0.999660727178, 0.00981073058949,
                               0, 0, 0, 1};
const double kT_BS_cam1[16] = {0.0125552670891, -0.999755099723, 0.0182237714554, -0.0198435579556,
                               0.999598781151,  0.0130119051815, 0.0251588363115, 0.0453689425024,
                               -0.0253898008918, 0.0179005838253, 0.999517347078, 0.00786212447038,
                               0, 0, 0, 1};

void expect_matrix(const Eigen::Isometry3d& T, const double (&rows)[16], double tol) {
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) EXPECT_NEAR(T.matrix()(r, c), rows[4 * r + c], tol) << r << "," << c;
}

}  // namespace

TEST(EurocSequence, LoadsStereoFixtureWithCalibration) {
  const auto seq = open_sequence(data_path("euroc_V1_01_easy_micro"));
  EXPECT_EQ(seq->format(), "euroc");
  ASSERT_EQ(seq->size(), 74u);
  const auto& calib = seq->calibration();
  ASSERT_TRUE(calib.stereo());
  EXPECT_EQ(calib.rate_hz, 20.0);

  const auto& c0 = *calib.cam0;
  EXPECT_EQ(c0.name(), "pinhole-radtan");
  EXPECT_EQ(c0.width(), 752);
  EXPECT_EQ(c0.height(), 480);
  EXPECT_EQ(c0.intrinsics().fx, 458.654);
  EXPECT_EQ(c0.intrinsics().fy, 457.296);
  EXPECT_EQ(c0.intrinsics().cx, 367.215);
  EXPECT_EQ(c0.intrinsics().cy, 248.375);
  EXPECT_EQ(c0.distortion(), (std::vector<double>{-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05, 0.0}));
  const auto& c1 = *calib.cam1;
  EXPECT_EQ(c1.intrinsics().fx, 457.587);
  EXPECT_EQ(c1.intrinsics().cy, 255.238);
  EXPECT_EQ(c1.distortion()[3], -3.55590700e-05);

  // T_BS as printed (rotation snapped to SO(3) moves entries by < 1e-9).
  expect_matrix(calib.T_body_cam0, kT_BS_cam0, 1e-9);
  expect_matrix(calib.T_body_cam1, kT_BS_cam1, 1e-9);
  EXPECT_EQ(calib.T_body_cam0.translation().x(), -0.0216401454975);

  // EuRoC's published stereo baseline is ~11 cm; rectification keeps it.
  EXPECT_NEAR(calib.baseline(), 0.110078, 1e-5);
  const pllvo::camera::StereoRectifier rect(calib.cam0, calib.cam1, calib.T_body_cam0, calib.T_body_cam1);
  EXPECT_NEAR(rect.baseline(), calib.baseline(), 1e-12);
  EXPECT_NEAR(rect.baseline(), 0.110, 5e-4);
}

TEST(EurocSequence, TimestampsAreNanosecondsOverOneBillion) {
  const auto seq = open_sequence(data_path("euroc_V1_01_easy_micro"));
  EXPECT_EQ(seq->timestamp(0), 1403715274312143104.0 / 1e9);
  EXPECT_EQ(seq->timestamp(73), 1403715277962142976.0 / 1e9);
  EXPECT_NEAR(seq->timestamp(1) - seq->timestamp(0), 0.05, 1e-6);
  EXPECT_EQ(seq->image_path(0, 0).filename(), "1403715274312143104.png");
  EXPECT_EQ(seq->image_path(73, 1).parent_path().parent_path().filename(), "cam1");
}

TEST(EurocSequence, GroundTruthIsWorldFromCam0) {
  const auto seq = open_sequence(data_path("euroc_V1_01_easy_micro"));
  ASSERT_TRUE(seq->ground_truth().has_value());
  const auto& gt = *seq->ground_truth();
  ASSERT_EQ(gt.size(), 733u);
  EXPECT_EQ(gt.stamps.front(), 1403715274307140000.0 / 1e9);
  EXPECT_EQ(gt.stamps.back(), 1403715277967140000.0 / 1e9);
  // First line: p = (0.878658, 2.142398, 0.947252), q_wxyz = (0.060571, -0.828433, -0.059051, -0.553664).
  Eigen::Isometry3d T_world_body = Eigen::Isometry3d::Identity();
  T_world_body.linear() = Eigen::Quaterniond(0.060571, -0.828433, -0.059051, -0.553664).normalized().toRotationMatrix();
  T_world_body.translation() = Eigen::Vector3d(0.878658, 2.142398, 0.947252);
  const Eigen::Isometry3d expected = T_world_body * seq->calibration().T_body_cam0;
  EXPECT_LT((gt.poses[0].matrix() - expected.matrix()).norm(), 1e-9);
  // The camera centre is 7 cm from the body origin (T_BS translation), not at it.
  EXPECT_NEAR((gt.poses[0].translation() - T_world_body.translation()).norm(),
              seq->calibration().T_body_cam0.translation().norm(), 1e-9);
}

TEST(EurocSequence, FramesAreTheRightGrayImages) {
  const auto seq = open_sequence(data_path("euroc_V1_01_easy_micro"));
  const Frame f0 = seq->frame(0);
  EXPECT_EQ(f0.index, 0u);
  EXPECT_EQ(f0.timestamp, seq->timestamp(0));
  ASSERT_EQ(f0.left.type(), CV_8UC1);
  EXPECT_EQ(f0.left.size(), cv::Size(752, 480));
  // Pixel sums computed independently by decoding the PNG files (zlib + PNG filters).
  EXPECT_EQ(pixel_sum(f0.left), 52478326.0);
  EXPECT_EQ(f0.left.at<uint8_t>(20, 10), 67);
  const Frame f73 = seq->frame(73);
  ASSERT_EQ(f73.right.type(), CV_8UC1);
  EXPECT_EQ(pixel_sum(f73.right), 47769605.0);
  EXPECT_EQ(f73.right.at<uint8_t>(20, 10), 74);
  EXPECT_THROW(seq->frame(74), std::out_of_range);
}

TEST(EurocSequence, MonoOptionAndMav0PathGiveTheLeftCameraOnly) {
  SequenceOptions mono;
  mono.mono = true;
  const auto seq = open_sequence(data_path("euroc_V1_01_easy_micro/mav0"), mono);
  EXPECT_EQ(seq->format(), "euroc");
  EXPECT_FALSE(seq->calibration().stereo());
  EXPECT_EQ(seq->calibration().baseline(), 0.0);
  ASSERT_EQ(seq->size(), 74u);
  const Frame f = seq->frame(5);
  EXPECT_FALSE(f.left.empty());
  EXPECT_TRUE(f.right.empty());
  EXPECT_TRUE(seq->ground_truth().has_value());
}

TEST(EurocSequence, StereoPairsByNearestTimeAndDropsUnpairedFrames) {
  TempDir tmp;
  const auto root = make_euroc_copy(tmp.path(), 4);
  // cam1: frame 1 removed, frame 2 stamped 0.4 ms late (within the 1 ms default tolerance).
  auto lines = read_lines(root / "mav0/cam1/data.csv");
  const std::string name2 = lines[3].substr(lines[3].find(',') + 1);
  lines[3] = std::to_string(std::stoll(lines[3].substr(0, lines[3].find(','))) + 400000) + "," + name2;
  lines.erase(lines.begin() + 2);
  write_lines(root / "mav0/cam1/data.csv", lines);

  const auto seq = open_sequence(root);
  ASSERT_EQ(seq->size(), 3u);
  EXPECT_EQ(seq->timestamp(0), 1403715274312143104.0 / 1e9);
  EXPECT_EQ(seq->timestamp(1), 1403715274412143104.0 / 1e9);  // cam0's stamp is kept
  EXPECT_EQ(seq->image_path(1, 1).filename(), name2);
  EXPECT_EQ(seq->image_path(1, 0).filename(), "1403715274412143104.png");

  SequenceOptions strict;
  strict.stereo_max_dt = 1e-4;
  EXPECT_EQ(open_sequence(root, strict)->size(), 2u);
}

TEST(EurocSequence, SensorYamlWithEquidistantModel) {
  TempDir tmp;
  auto text = read_file(data_path("euroc_V1_01_easy_micro/mav0/cam0/sensor.yaml"));
  text.replace(text.find("radial-tangential"), 17, "equidistant");
  const size_t at = text.find("distortion_coefficients");
  text = text.substr(0, at) + "distortion_coefficients: [0.01, -0.02, 0.003, -0.0004]\n";
  write_file(tmp / "sensor.yaml", text);
  const auto sensor = read_euroc_sensor_yaml(tmp / "sensor.yaml");
  EXPECT_EQ(sensor.camera->name(), "kannala-brandt");
  EXPECT_EQ(sensor.camera->distortion(), (std::vector<double>{0.01, -0.02, 0.003, -0.0004}));
  EXPECT_EQ(sensor.camera->intrinsics().cx, 367.215);
  EXPECT_EQ(sensor.rate_hz, 20.0);
}
