#include <gtest/gtest.h>

#include "pllvo/camera/stereo_rectifier.h"

using namespace pllvo::camera;

namespace {
Eigen::Isometry3d from_rows(std::initializer_list<double> v) {
  Eigen::Matrix4d M;
  auto it = v.begin();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) M(r, c) = *it++;
  Eigen::Isometry3d T;
  T.matrix() = M;
  return T;
}
// EuRoC V1 calibration (cam0/cam1 sensor.yaml).
CameraPtr euroc_cam0() {
  return std::make_shared<PinholeRadtan>(752, 480, PinholeIntrinsics{458.654, 457.296, 367.215, 248.375},
                                         std::vector<double>{-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05});
}
CameraPtr euroc_cam1() {
  return std::make_shared<PinholeRadtan>(752, 480, PinholeIntrinsics{457.587, 456.134, 379.999, 255.238},
                                         std::vector<double>{-0.28368365, 0.07451284, -0.00010473, -3.55590700e-05});
}
const Eigen::Isometry3d T_b_c0 = from_rows({0.0148655429818, -0.999880929698, 0.00414029679422, -0.0216401454975,
                                            0.999557249008, 0.0149672133247, 0.025715529948, -0.064676986768,
                                            -0.0257744366974, 0.00375618835797, 0.999660727178, 0.00981073058949,
                                            0, 0, 0, 1});
const Eigen::Isometry3d T_b_c1 = from_rows({0.0125552670891, -0.999755099723, 0.0182237714554, -0.0198435579556,
                                            0.999598781151, 0.0130119051815, 0.0251588363115, 0.0453689425024,
                                            -0.0253898008918, 0.0179005838253, 0.999517347078, 0.00786212447038,
                                            0, 0, 0, 1});

/// Raw pixels of camera `cam` under the border of a pinhole view (K, rotation R_view_cam, size view):
/// the smallest distance of any of them inside the raw image's edges (negative: outside), and
/// per raw side, the smallest distance from that side.
struct BorderReach {
  double inside = 1e9;
  double left = 1e9, right = 1e9, top = 1e9, bottom = 1e9;
};
BorderReach border_reach(const CameraModel& cam, const PinholeIntrinsics& K, const Eigen::Matrix3d& R_view_cam,
                         cv::Size view = {752, 480}) {
  BorderReach r;
  const double w = cam.width() - 1.0, h = cam.height() - 1.0;
  const double vw = view.width - 1.0, vh = view.height - 1.0;
  auto visit = [&](double u, double v) {
    const Eigen::Vector3d ray_view((u - K.cx) / K.fx, (v - K.cy) / K.fy, 1.0);
    Eigen::Vector2d uv;
    ASSERT_TRUE(cam.project(R_view_cam.transpose() * ray_view, uv));
    r.inside = std::min({r.inside, uv.x(), uv.y(), w - uv.x(), h - uv.y()});
    r.left = std::min(r.left, uv.x());
    r.right = std::min(r.right, w - uv.x());
    r.top = std::min(r.top, uv.y());
    r.bottom = std::min(r.bottom, h - uv.y());
  };
  for (int i = 0; i <= 200; ++i) {
    const double t = i / 200.0;
    visit(0, t * vh), visit(vw, t * vh), visit(t * vw, 0), visit(t * vw, vh);
  }
  return r;
}
}  // namespace

TEST(StereoRectifier, EurocPairGivesHorizontalEpipolarLines) {
  const auto cam0 = euroc_cam0(), cam1 = euroc_cam1();
  const StereoRectifier rect(cam0, cam1, T_b_c0, T_b_c1);
  EXPECT_NEAR(rect.baseline(), 0.110078, 1e-4);  // EuRoC's published ~11 cm baseline

  // A 3-D point seen by both original cameras must land on the same rectified row,
  // with disparity f*b/z in the rectified views.
  const Eigen::Isometry3d T_c1_c0 = T_b_c1.inverse() * T_b_c0;
  const auto& K = rect.rectified_intrinsics();
  for (double x : {-1.0, 0.0, 0.8})
    for (double y : {-0.5, 0.4})
      for (double z : {2.0, 5.0}) {
        const Eigen::Vector3d p0(x, y, z);
        const Eigen::Vector3d r0 = rect.R_rect_cam(0) * p0;
        const Eigen::Vector3d r1 = rect.R_rect_cam(1) * (T_c1_c0 * p0);
        const double v0 = K.fy * r0.y() / r0.z() + K.cy, v1 = K.fy * r1.y() / r1.z() + K.cy;
        const double u0 = K.fx * r0.x() / r0.z() + K.cx, u1 = K.fx * r1.x() / r1.z() + K.cx;
        EXPECT_NEAR(v0, v1, 1e-6);
        EXPECT_NEAR(u0 - u1, K.fx * rect.baseline() / r0.z(), 1e-6);
      }
  // Rectified right camera sits at +baseline along x of the rectified left one.
  const Eigen::Vector3d c1_in_r0 = rect.R_rect_cam(0) * (T_c1_c0.inverse().translation());
  EXPECT_NEAR(c1_in_r0.x(), rect.baseline(), 1e-9);
  EXPECT_NEAR(c1_in_r0.y(), 0.0, 1e-9);
  EXPECT_NEAR(c1_in_r0.z(), 0.0, 1e-9);
  // A distorted, rotated pair: its images are resampled.
  EXPECT_FALSE(rect.is_identity(0));
  EXPECT_FALSE(rect.is_identity(1));
  const cv::Mat image(480, 752, CV_8UC1, cv::Scalar(90));
  EXPECT_NE(rect.rectify(0, image).data, image.data);
}

// An already rectified pair (equal pinhole cameras, baseline along x: a synthetic rig, KITTI)
// maps every pixel onto itself, so its images pass through unchanged and uncopied.
TEST(StereoRectifier, AnAlreadyRectifiedPairPassesImagesThrough) {
  const PinholeIntrinsics k{460.0, 460.0, 376.0, 240.0};
  auto cam0 = std::make_shared<PinholeRadtan>(752, 480, k, std::vector<double>{0, 0, 0, 0});
  auto cam1 = std::make_shared<PinholeRadtan>(752, 480, k, std::vector<double>{0, 0, 0, 0});
  Eigen::Isometry3d T_b_c1 = Eigen::Isometry3d::Identity();
  T_b_c1.translation() = Eigen::Vector3d(0.11, 0, 0);
  const StereoRectifier rect(cam0, cam1, Eigen::Isometry3d::Identity(), T_b_c1);
  ASSERT_TRUE(rect.is_identity(0));
  ASSERT_TRUE(rect.is_identity(1));
  EXPECT_NEAR(rect.baseline(), 0.11, 1e-12);
  cv::Mat image(480, 752, CV_8UC1);
  cv::randu(image, 0, 255);
  EXPECT_EQ(rect.rectify(0, image).data, image.data);
  EXPECT_EQ(rect.rectify(1, image).data, image.data);
  // A small rotation of the right camera makes rectification resample again.
  T_b_c1.linear() = Eigen::AngleAxisd(0.01, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const StereoRectifier rotated(cam0, cam1, Eigen::Isometry3d::Identity(), T_b_c1);
  EXPECT_FALSE(rotated.is_identity(1));
}

// EuRoC's barrel distortion (k1 = -0.28): at the calibrated focal length and image size the
// undistorted view loses the raw image's sides (its border maps ~55 px inside raw columns 0 and
// 751). "fit" shrinks the focal lengths and "whole" enlarges the image until the view's border
// touches every raw side; both stay inside it.
TEST(WorkingView, EurocCameraSpansTheRawImageFromSideToSide) {
  const auto cam = euroc_cam0();
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  const cv::Size size(752, 480);
  const PinholeView calibrated = working_view({cam.get()}, {I}, cam->intrinsics(), size, WorkingView::calibrated);
  const BorderReach cropped = border_reach(*cam, calibrated.K, I);
  EXPECT_GT(cropped.left, 40.0);
  EXPECT_GT(cropped.right, 40.0);

  const PinholeView fit = working_view({cam.get()}, {I}, cam->intrinsics(), size, WorkingView::fit);
  EXPECT_EQ(fit.size, size);
  EXPECT_LT(fit.K.fx, 0.8 * cam->intrinsics().fx);  // 356 px: ~29 % more field of view across
  EXPECT_LT(fit.K.fy, cam->intrinsics().fy);
  const PinholeView whole = working_view({cam.get()}, {I}, cam->intrinsics(), size, WorkingView::whole);
  EXPECT_EQ(whole.K.fx, cam->intrinsics().fx);
  EXPECT_EQ(whole.K.fy, cam->intrinsics().fy);
  EXPECT_GT(whole.size.width, 1.25 * size.width);  // 968 x 526
  EXPECT_GT(whole.size.height, size.height);
  for (const PinholeView& v : {fit, whole}) {
    const BorderReach b = border_reach(*cam, v.K, I, v.size);
    EXPECT_GE(b.inside, -0.05);  // raw pixels only: no black border
    for (double side : {b.left, b.right, b.top, b.bottom}) EXPECT_LT(side, 1.0);
  }
}

// Rectified "fit" views keep the stereo geometry: rows agree, disparity is f b / z, and their
// border lies inside both raw images, touching them.
TEST(WorkingView, RectifiedEurocPairKeepsRowsAndStaysInsideBothImages) {
  const auto cam0 = euroc_cam0(), cam1 = euroc_cam1();
  const StereoRectifier calibrated(cam0, cam1, T_b_c0, T_b_c1);
  const StereoRectifier rect(cam0, cam1, T_b_c0, T_b_c1, WorkingView::fit);
  const auto& K = rect.rectified_intrinsics();
  EXPECT_LT(K.fx, 0.8 * calibrated.rectified_intrinsics().fx);
  EXPECT_EQ(rect.view_size(), rect.size());
  EXPECT_NEAR(rect.baseline(), calibrated.baseline(), 1e-12);
  const Eigen::Isometry3d T_c1_c0 = T_b_c1.inverse() * T_b_c0;
  for (double x : {-1.5, 0.0, 1.2})
    for (double z : {2.0, 5.0}) {
      const Eigen::Vector3d p0(x, 0.3, z);
      const Eigen::Vector3d r0 = rect.R_rect_cam(0) * p0, r1 = rect.R_rect_cam(1) * (T_c1_c0 * p0);
      EXPECT_NEAR(K.fy * r0.y() / r0.z(), K.fy * r1.y() / r1.z(), 1e-6);
      EXPECT_NEAR(K.fx * (r0.x() / r0.z() - r1.x() / r1.z()), K.fx * rect.baseline() / r0.z(), 1e-6);
    }
  const BorderReach b0 = border_reach(*cam0, K, rect.R_rect_cam(0), rect.view_size());
  const BorderReach b1 = border_reach(*cam1, K, rect.R_rect_cam(1), rect.view_size());
  EXPECT_GE(std::min(b0.inside, b1.inside), -0.05);
  // Each side of the view touches one of the two raw images.
  EXPECT_LT(std::min(b0.left, b1.left), 1.0);
  EXPECT_LT(std::min(b0.right, b1.right), 1.0);
  EXPECT_LT(std::min(b0.top, b1.top), 1.0);
  EXPECT_LT(std::min(b0.bottom, b1.bottom), 1.0);
  // Rectified images have the view's size.
  const cv::Mat image(480, 752, CV_8UC1, cv::Scalar(90));
  const StereoRectifier whole(cam0, cam1, T_b_c0, T_b_c1, WorkingView::whole);
  EXPECT_EQ(whole.rectify(0, image).size(), whole.view_size());
  EXPECT_GT(whole.view_size().width, 900);
}

// A camera without distortion has nothing cropped: every working view is the calibrated one,
// and an already rectified pair still passes its images through.
TEST(WorkingView, UndistortedCamerasKeepTheirIntrinsics) {
  const PinholeIntrinsics k{460.0, 460.0, 376.0, 240.0};
  auto cam0 = std::make_shared<PinholeRadtan>(752, 480, k, std::vector<double>{0, 0, 0, 0});
  auto cam1 = std::make_shared<PinholeRadtan>(752, 480, k, std::vector<double>{0, 0, 0, 0});
  for (WorkingView view : {WorkingView::fit, WorkingView::whole}) {
    const PinholeView v = working_view({cam0.get()}, {Eigen::Matrix3d::Identity()}, k, {752, 480}, view);
    EXPECT_EQ(v.K.fx, k.fx);
    EXPECT_EQ(v.K.fy, k.fy);
    EXPECT_EQ(v.K.cx, k.cx);
    EXPECT_EQ(v.K.cy, k.cy);
    EXPECT_EQ(v.size, cv::Size(752, 480));
    Eigen::Isometry3d T_b_c1 = Eigen::Isometry3d::Identity();
    T_b_c1.translation() = Eigen::Vector3d(0.11, 0, 0);
    const StereoRectifier rect(cam0, cam1, Eigen::Isometry3d::Identity(), T_b_c1, view);
    EXPECT_TRUE(rect.is_identity(0));
    EXPECT_TRUE(rect.is_identity(1));
  }
}
