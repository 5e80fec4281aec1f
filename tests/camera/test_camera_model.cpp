#include <gtest/gtest.h>

#include <Eigen/Core>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include "pllvo/camera/camera_model.h"
#include "pllvo/common/error.h"

using namespace pllvo::camera;

namespace {
// EuRoC V1 cam0 and a TUM-VI-like fisheye.
PinholeRadtan euroc_cam() {
  return PinholeRadtan(752, 480, {458.654, 457.296, 367.215, 248.375},
                       {-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05});
}
KannalaBrandt fisheye_cam() {
  return KannalaBrandt(512, 512, {190.978, 190.973, 254.932, 256.897},
                       {0.00348238, 0.000715034, -0.00205323, 0.000202937});
}

Eigen::Matrix<double, 2, 3> numeric_jacobian(const CameraModel& cam, const Eigen::Vector3d& p) {
  Eigen::Matrix<double, 2, 3> J;
  for (int k = 0; k < 3; ++k) {
    Eigen::Vector3d d = Eigen::Vector3d::Zero();
    d[k] = 1e-6;
    Eigen::Vector2d a, b;
    EXPECT_TRUE(cam.project(p + d, a));
    EXPECT_TRUE(cam.project(p - d, b));
    J.col(k) = (a - b) / 2e-6;
  }
  return J;
}

std::vector<Eigen::Vector3d> sample_points(double max_angle_deg) {
  std::vector<Eigen::Vector3d> pts;
  cv::RNG rng(7);
  for (int i = 0; i < 200; ++i) {
    const double a = rng.uniform(0.0, max_angle_deg) * M_PI / 180, phi = rng.uniform(0.0, 2 * M_PI);
    const double depth = rng.uniform(0.5, 20.0);
    pts.emplace_back(depth * std::sin(a) * std::cos(phi), depth * std::sin(a) * std::sin(phi),
                     depth * std::cos(a));
  }
  return pts;
}
}  // namespace

TEST(PinholeRadtan, JacobianMatchesNumeric) {
  const auto cam = euroc_cam();
  for (const auto& p : sample_points(35)) {
    Eigen::Vector2d uv;
    Eigen::Matrix<double, 2, 3> J;
    ASSERT_TRUE(cam.project(p, uv, &J));
    EXPECT_LT((J - numeric_jacobian(cam, p)).cwiseAbs().maxCoeff(), 1e-4 * (1 + J.norm()));
  }
}

TEST(PinholeRadtan, MatchesOpenCVProjectPoints) {
  const auto cam = euroc_cam();
  const auto pts = sample_points(35);
  std::vector<cv::Point3d> cv_pts;
  for (const auto& p : pts) cv_pts.emplace_back(p.x(), p.y(), p.z());
  cv::Mat K;
  cv::eigen2cv(cam.intrinsics().K(), K);
  std::vector<cv::Point2d> ref;
  cv::projectPoints(cv_pts, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K, cam.distortion(), ref);
  for (size_t i = 0; i < pts.size(); ++i) {
    Eigen::Vector2d uv;
    ASSERT_TRUE(cam.project(pts[i], uv));
    EXPECT_NEAR(uv.x(), ref[i].x, 1e-9);
    EXPECT_NEAR(uv.y(), ref[i].y, 1e-9);
  }
}

TEST(PinholeRadtan, UnprojectInvertsProject) {
  const auto cam = euroc_cam();
  for (const auto& p : sample_points(35)) {
    Eigen::Vector2d uv;
    Eigen::Vector3d b;
    ASSERT_TRUE(cam.project(p, uv));
    ASSERT_TRUE(cam.unproject(uv, b));
    EXPECT_NEAR(b.norm(), 1.0, 1e-12);
    EXPECT_LT((b - p.normalized()).norm(), 1e-9);
  }
}

TEST(PinholeRadtan, RejectsPointsBehind) {
  const auto cam = euroc_cam();
  Eigen::Vector2d uv;
  EXPECT_FALSE(cam.project({0.1, 0.2, -1.0}, uv));
  EXPECT_FALSE(cam.project({0.1, 0.2, 0.0}, uv));
}

TEST(PinholeRadtan, UndistortPointsMatchesOpenCV) {
  const auto cam = euroc_cam();
  std::vector<Eigen::Vector2d> px;
  std::vector<cv::Point2d> cv_px;
  for (int v = 20; v < 480; v += 90)
    for (int u = 20; u < 752; u += 120) {
      px.emplace_back(u, v);
      cv_px.emplace_back(u, v);
    }
  cv::Mat K;
  cv::eigen2cv(cam.intrinsics().K(), K);
  std::vector<cv::Point2d> ref;
  cv::undistortPoints(cv_px, ref, K, cam.distortion(), cv::noArray(), K,
                      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 100, 1e-14));
  const auto got = cam.undistort_points(px);
  for (size_t i = 0; i < px.size(); ++i) {
    EXPECT_NEAR(got[i].x(), ref[i].x, 1e-3);
    EXPECT_NEAR(got[i].y(), ref[i].y, 1e-3);
  }
}

TEST(KannalaBrandt, JacobianMatchesNumeric) {
  const auto cam = fisheye_cam();
  for (const auto& p : sample_points(85)) {
    Eigen::Vector2d uv;
    Eigen::Matrix<double, 2, 3> J;
    ASSERT_TRUE(cam.project(p, uv, &J));
    EXPECT_LT((J - numeric_jacobian(cam, p)).cwiseAbs().maxCoeff(), 1e-4 * (1 + J.norm()));
  }
}

TEST(KannalaBrandt, MatchesOpenCVFisheye) {
  const auto cam = fisheye_cam();
  const auto pts = sample_points(80);
  std::vector<cv::Point3d> cv_pts;
  for (const auto& p : pts) cv_pts.emplace_back(p.x(), p.y(), p.z());
  cv::Mat K;
  cv::eigen2cv(cam.intrinsics().K(), K);
  std::vector<cv::Point2d> ref;
  cv::fisheye::projectPoints(cv_pts, ref, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K, cam.distortion());
  for (size_t i = 0; i < pts.size(); ++i) {
    Eigen::Vector2d uv;
    ASSERT_TRUE(cam.project(pts[i], uv));
    EXPECT_NEAR(uv.x(), ref[i].x, 1e-7);
    EXPECT_NEAR(uv.y(), ref[i].y, 1e-7);
  }
}

TEST(KannalaBrandt, UnprojectInvertsProjectBeyond90Degrees) {
  const auto cam = fisheye_cam();
  for (const auto& p : sample_points(95)) {
    Eigen::Vector2d uv;
    Eigen::Vector3d b;
    ASSERT_TRUE(cam.project(p, uv));
    ASSERT_TRUE(cam.unproject(uv, b));
    EXPECT_LT((b - p.normalized()).norm(), 1e-9);
  }
  Eigen::Vector2d uv;
  Eigen::Matrix<double, 2, 3> J;
  ASSERT_TRUE(cam.project({0, 0, 2.0}, uv, &J));  // on the axis
  EXPECT_NEAR(uv.x(), cam.intrinsics().cx, 1e-12);
  EXPECT_NEAR(J(0, 0), cam.intrinsics().fx / 2.0, 1e-9);
}

TEST(CameraModel, UndistortImageKeepsStraightLinesStraight) {
  const auto cam = euroc_cam();
  // Render the distorted image of a straight 3-D line, undistort, check collinearity.
  cv::Mat img(480, 752, CV_8UC1, cv::Scalar(0));
  for (double s = -1.5; s <= 1.5; s += 0.0005) {
    Eigen::Vector2d uv;
    if (cam.project({s, 0.3, 1.0}, uv) && cam.in_image(uv, 1))
      img.at<uint8_t>(static_cast<int>(std::lround(uv.y())), static_cast<int>(std::lround(uv.x()))) = 255;
  }
  const cv::Mat und = cam.undistort_image(img);
  // Ideal row of the line: v = fy * 0.6 + cy.
  const double v_ideal = cam.intrinsics().fy * 0.3 + cam.intrinsics().cy;
  int checked = 0;
  for (int u = 100; u < 650; u += 25) {
    double sum = 0, w = 0;
    for (int v = 0; v < 480; ++v) {
      sum += v * und.at<uint8_t>(v, u);
      w += und.at<uint8_t>(v, u);
    }
    if (w == 0) continue;
    EXPECT_NEAR(sum / w, v_ideal, 1.0) << "column " << u;
    ++checked;
  }
  EXPECT_GT(checked, 15);
}

TEST(CameraModel, RejectsBadParameters) {
  EXPECT_THROW(PinholeRadtan(0, 480, {400, 400, 300, 200}), pllvo::InputError);
  EXPECT_THROW(PinholeRadtan(640, 480, {-1, 400, 300, 200}), pllvo::InputError);
  EXPECT_THROW(PinholeRadtan(640, 480, {400, 400, 300, 200}, {0.1, 0.2}), pllvo::InputError);
  EXPECT_THROW(PinholeRadtan(640, 480, {400, NAN, 300, 200}), pllvo::InputError);
  EXPECT_THROW(KannalaBrandt(640, 480, {400, 400, 300, 200}, {0.1}), pllvo::InputError);
}
