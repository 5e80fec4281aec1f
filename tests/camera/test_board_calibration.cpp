// Camera calibration (pllvo calibrate) on boards rendered with known intrinsics and distortion:
// plain OpenCV drawing, a perspective warp at 4x resolution averaged down (anti-aliased edges),
// then the lens's distortion applied by remapping every pixel through the true model.
#include <cmath>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <Eigen/Core>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgproc.hpp>

#include <unistd.h>

#include "pllvo/camera/board_calibration.h"
#include "pllvo/camera/camera_yaml.h"
#include "pllvo/common/error.h"
#include "pllvo/io/calibration_file.h"
#include "../support/cli_runner.h"

namespace pllvo::camera {
namespace {

struct Lens {
  cv::Size size{640, 480};
  double fx = 520, fy = 515, cx = 322.5, cy = 241.0;
  bool fisheye = false;
  std::vector<double> dist{-0.25, 0.08, 0.001, -0.0005, 0.0};  // radtan k1 k2 p1 p2 k3; fisheye k1..k4
  cv::Mat K(double scale = 1.0, double offset = 0.0) const {
    // Pixel centres at integers: the 4x image's pixel (4u + 1.5) is the 1x image's pixel u.
    return (cv::Mat_<double>(3, 3) << scale * fx, 0, scale * (cx + offset) + (scale - 1) / 2, 0, scale * fy,
            scale * (cy + offset) + (scale - 1) / 2, 0, 0, 1);
  }
};

cv::Matx33d rotation(double ax, double ay, double az) {
  cv::Mat R;
  cv::Rodrigues(cv::Vec3d(ax, ay, az), R);
  return cv::Matx33d(R);
}

/// The board seen by the lens from pose (R, t) of the board in the camera frame.
cv::Mat render(const BoardSpec& board, const Lens& lens, const cv::Matx33d& R, const cv::Vec3d& t) {
  const int pps = 60, margin = 200, scale = 4;
  const cv::Mat texture = draw_board(board, pps);
  // Texture pixel centre (px, py) is the board point ((px + 0.5) / pps - 1) * square: the board's
  // outer corner, where detect_board's coordinates start, is texture pixel pps.
  const double s = board.square_m / pps, o = (0.5 / pps - 1) * board.square_m;
  const cv::Matx33d A(s, 0, o, 0, s, o, 0, 0, 1);
  const cv::Matx33d Rt(R(0, 0), R(0, 1), t[0], R(1, 0), R(1, 1), t[1], R(2, 0), R(2, 1), t[2]);
  const cv::Size ideal_size(lens.size.width + 2 * margin, lens.size.height + 2 * margin);
  cv::Mat big, ideal;
  const cv::Matx33d H = cv::Matx33d(lens.K(scale, margin)) * Rt * A;
  cv::warpPerspective(texture, big, H, ideal_size * scale, cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(128));
  cv::resize(big, ideal, ideal_size, 0, 0, cv::INTER_AREA);
  // Each pixel of the distorted image shows what the ideal (pinhole) image has at its undistorted position.
  std::vector<cv::Point2f> pixels, undistorted;
  for (int v = 0; v < lens.size.height; ++v)
    for (int u = 0; u < lens.size.width; ++u) pixels.emplace_back(static_cast<float>(u), static_cast<float>(v));
  if (lens.fisheye)
    cv::fisheye::undistortPoints(pixels, undistorted, lens.K(), lens.dist, cv::noArray(), lens.K());
  else
    cv::undistortPoints(pixels, undistorted, lens.K(), lens.dist, cv::noArray(), lens.K());
  cv::Mat map(lens.size, CV_32FC2);
  for (size_t i = 0; i < undistorted.size(); ++i)
    map.at<cv::Vec2f>(static_cast<int>(i / lens.size.width), static_cast<int>(i % lens.size.width)) =
        cv::Vec2f(undistorted[i].x + margin, undistorted[i].y + margin);
  cv::Mat image;
  cv::remap(ideal, image, map, cv::noArray(), cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(128));
  return image;
}

/// Views from the left, right, top, bottom, near and far, tilted up to ~35 deg.
/// `distance`: the board's mean distance (metres); near enough that the views cover the middle of the image.
std::vector<std::pair<std::string, cv::Mat>> views(const BoardSpec& board, const Lens& lens, int n = 14,
                                                   double distance = 0.42) {
  std::vector<std::pair<std::string, cv::Mat>> out;
  const double w = (board.cols + 2) * board.square_m, h = (board.rows + 2) * board.square_m;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * M_PI * i / n;
    const cv::Matx33d R = rotation(0.5 * std::sin(a), 0.55 * std::cos(1.3 * a), 0.2 * std::sin(2 * a));
    const cv::Vec3d centre = R * cv::Vec3d(w / 2, h / 2, 0);
    const double z = distance + 0.1 * std::sin(3 * a);
    const cv::Vec3d t = cv::Vec3d(0.07 * std::cos(a), 0.05 * std::sin(a), z) - centre;
    out.emplace_back("view" + std::to_string(i), render(board, lens, R, t));
  }
  return out;
}

/// The largest distance (pixels) between where the lens and the calibrated model put the same
/// bearing, over a grid on the part of the image the boards covered (the middle 70 % of each side;
/// beyond it the fitted polynomial extrapolates): the distortion's error as it matters.
double max_projection_error(const CameraModel& c, const Lens& lens) {
  std::vector<cv::Point2f> pixels, normalised;
  for (double fv = 0.15; fv <= 0.851; fv += 0.05)
    for (double fu = 0.15; fu <= 0.851; fu += 0.05)
      pixels.emplace_back(static_cast<float>(fu * lens.size.width), static_cast<float>(fv * lens.size.height));
  if (lens.fisheye)
    cv::fisheye::undistortPoints(pixels, normalised, lens.K(), lens.dist);
  else
    cv::undistortPoints(pixels, normalised, lens.K(), lens.dist);
  double worst = 0;
  for (size_t i = 0; i < pixels.size(); ++i) {
    Eigen::Vector2d uv;
    if (!c.project(Eigen::Vector3d(normalised[i].x, normalised[i].y, 1.0), uv)) return 1e9;
    worst = std::max(worst, (uv - Eigen::Vector2d(pixels[i].x, pixels[i].y)).norm());
  }
  return worst;
}

void expect_intrinsics(const CameraModel& c, const Lens& lens) {
  const auto& k = c.intrinsics();
  EXPECT_NEAR(k.fx, lens.fx, 0.005 * lens.fx);
  EXPECT_NEAR(k.fy, lens.fy, 0.005 * lens.fy);
  EXPECT_NEAR(k.cx, lens.cx, 0.005 * lens.cx);
  EXPECT_NEAR(k.cy, lens.cy, 0.005 * lens.cy);
}

BoardSpec chessboard() {
  BoardSpec b;
  b.rows = 6;
  b.cols = 9;
  b.square_m = 0.03;
  return b;
}

TEST(BoardCalibration, ChessboardRecoversPinholeRadtanIntrinsics) {
  const Lens lens;
  const BoardCalibration c = calibrate_camera(views(chessboard(), lens), chessboard());
  expect_intrinsics(*c.camera, lens);
  const auto d = c.camera->distortion();
  ASSERT_GE(d.size(), 4u);
  EXPECT_NEAR(d[0], lens.dist[0], 0.01);   // k1
  EXPECT_NEAR(d[2], lens.dist[2], 0.001);  // p1
  EXPECT_NEAR(d[3], lens.dist[3], 0.001);  // p2
  EXPECT_LT(max_projection_error(*c.camera, lens), 1.5);  // k2 and k3 trade against each other; the lens is right
  EXPECT_LT(c.rms_px, 0.2);
  for (const auto& v : c.views) EXPECT_TRUE(v.found) << v.name;
}

TEST(BoardCalibration, CharucoRecoversTheSameIntrinsics) {
  BoardSpec b;
  b.type = "charuco";
  b.rows = 6;
  b.cols = 8;
  b.square_m = 0.035;
  const Lens lens;
  const BoardCalibration c = calibrate_camera(views(b, lens), b);
  expect_intrinsics(*c.camera, lens);
  EXPECT_NEAR(c.camera->distortion()[0], lens.dist[0], 0.01);
  EXPECT_LT(max_projection_error(*c.camera, lens), 1.5);
  EXPECT_LT(c.rms_px, 0.3);
}

TEST(BoardCalibration, EquidistantModelForAFisheyeLens) {
  Lens lens;
  lens.fisheye = true;
  lens.fx = 380, lens.fy = 378;
  lens.dist = {-0.02, 0.01, -0.005, 0.001};
  CalibrationOptions options;
  options.model = "equidistant";
  const CameraPtr truth = make_camera("equidistant", lens.size.width, lens.size.height,
                                      PinholeIntrinsics{lens.fx, lens.fy, lens.cx, lens.cy}, lens.dist);
  EXPECT_LT(max_projection_error(*truth, lens), 0.01);  // pllvo's Kannala-Brandt is OpenCV's fisheye model
  // The wider lens sees the board smaller: nearer views cover as much of the image.
  const BoardCalibration c = calibrate_camera(views(chessboard(), lens, 14, 0.3), chessboard(), options);
  EXPECT_EQ(c.camera->name(), "kannala-brandt");
  expect_intrinsics(*c.camera, lens);
  // k1..k4 of a mild fisheye trade against each other and the focal length: the lens is what is checked.
  EXPECT_LT(max_projection_error(*c.camera, lens), 1.0);
  EXPECT_LT(c.rms_px, 0.2);
}

TEST(BoardCalibration, StereoPairGivesTheBaseline) {
  const Lens lens;
  const BoardSpec b = chessboard();
  // The right camera 10 cm to the right: the board is 10 cm further left in its frame.
  const int n = 16;
  std::vector<std::pair<std::string, cv::Mat>> left = views(b, lens, n), right;
  const double w = (b.cols + 2) * b.square_m, h = (b.rows + 2) * b.square_m;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * M_PI * i / n;
    const cv::Matx33d R = rotation(0.5 * std::sin(a), 0.55 * std::cos(1.3 * a), 0.2 * std::sin(2 * a));
    const cv::Vec3d t = cv::Vec3d(0.07 * std::cos(a), 0.05 * std::sin(a), 0.42 + 0.1 * std::sin(3 * a)) -
                        R * cv::Vec3d(w / 2, h / 2, 0) - cv::Vec3d(0.10, 0, 0);
    right.emplace_back("right" + std::to_string(i), render(b, lens, R, t));
  }
  const StereoBoardCalibration s = calibrate_stereo(left, right, b);
  EXPECT_NEAR(s.T_left_right.translation().x(), 0.10, 0.002);
  EXPECT_NEAR(s.T_left_right.translation().y(), 0.0, 0.002);
  EXPECT_LT(Eigen::AngleAxisd(s.T_left_right.linear()).angle(), 0.006);  // 0.35 deg (measured 0.2 deg, 10 pairs)
  const auto file = std::filesystem::temp_directory_path() / ("pllvo_camchain_" + std::to_string(::getpid()) + ".yaml");
  io::save_kalibr_camchain(*s.left.camera, s.right.camera.get(), s.T_left_right, file);
  const io::Calibration read = io::load_calibration_file(file);
  ASSERT_TRUE(read.stereo());
  EXPECT_NEAR(read.baseline(), s.T_left_right.translation().norm(), 1e-12);
  EXPECT_NEAR(read.cam1->intrinsics().fx, s.right.camera->intrinsics().fx, 1e-9);
}

TEST(BoardCalibration, TooFewBoardsIsRefusedWithTheCount) {
  const Lens lens;
  auto v = views(chessboard(), lens, 4);
  v.emplace_back("blank", cv::Mat(lens.size, CV_8UC1, cv::Scalar(128)));
  try {
    calibrate_camera(v, chessboard());
    FAIL() << "calibrated from 4 views";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("found in 4 of 5 images"), std::string::npos) << e.what();
  }
  BoardSpec wrong = chessboard();
  wrong.square_m = 0;
  EXPECT_THROW(calibrate_camera(v, wrong), InputError);
}

TEST(BoardCalibration, CliWritesTheCameraYamlAndRefusesTooFewViews) {
  const Lens lens;
  const auto dir = std::filesystem::temp_directory_path() / ("pllvo_calibrate_cli_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir / "shots");
  for (const auto& [name, image] : views(chessboard(), lens, 8)) cv::imwrite((dir / "shots" / (name + ".png")).string(), image);
  const auto r = test::run_cli("calibrate " + (dir / "shots").string() +
                               " --board chessboard --rows 6 --cols 9 --square 0.03 --out " + (dir / "camera.yaml").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("board found in 8 of 8 images"), std::string::npos) << r.output;
  const CameraPtr c = load_camera_yaml(dir / "camera.yaml");
  EXPECT_NEAR(c->intrinsics().fx, lens.fx, 0.005 * lens.fx);
  // Too few views: refused, nothing written.
  std::filesystem::remove(dir / "camera.yaml");
  for (int i = 2; i < 8; ++i) std::filesystem::remove(dir / "shots" / ("view" + std::to_string(i) + ".png"));
  const auto few = test::run_cli("calibrate " + (dir / "shots").string() +
                                 " --board chessboard --rows 6 --cols 9 --square 0.03 --out " + (dir / "camera.yaml").string());
  EXPECT_EQ(few.exit_code, 2) << few.output;
  EXPECT_NE(few.output.find("found in 2 of 2 images"), std::string::npos) << few.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "camera.yaml"));
}

TEST(CalibrationFiles, ReadsOpenCvsCalibrationOutput) {
  const auto file = std::filesystem::temp_directory_path() / ("pllvo_opencv_calib_" + std::to_string(::getpid()) + ".yml");
  {
    cv::FileStorage fs(file.string(), cv::FileStorage::WRITE);
    fs << "image_width" << 640 << "image_height" << 480;
    fs << "camera_matrix" << (cv::Mat_<double>(3, 3) << 500, 0, 320, 0, 501, 240, 0, 0, 1);
    fs << "distortion_coefficients" << (cv::Mat_<double>(1, 5) << -0.2, 0.05, 0.001, 0.002, 0.0);
  }
  const io::Calibration c = io::load_calibration_file(file);
  EXPECT_EQ(c.cam0->width(), 640);
  EXPECT_DOUBLE_EQ(c.cam0->intrinsics().fy, 501);
  EXPECT_DOUBLE_EQ(c.cam0->distortion()[0], -0.2);
  EXPECT_FALSE(c.stereo());
  std::ofstream(file) << "%YAML:1.0\ncamera_matrix: [1, 2]\n";
  EXPECT_THROW(io::load_calibration_file(file), InputError);
}

}  // namespace
}  // namespace pllvo::camera
