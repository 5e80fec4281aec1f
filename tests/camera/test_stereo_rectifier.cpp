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
}  // namespace

// EuRoC V1 calibration (cam0/cam1 sensor.yaml).
TEST(StereoRectifier, EurocPairGivesHorizontalEpipolarLines) {
  auto cam0 = std::make_shared<PinholeRadtan>(752, 480, PinholeIntrinsics{458.654, 457.296, 367.215, 248.375},
                                              std::vector<double>{-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05});
  auto cam1 = std::make_shared<PinholeRadtan>(752, 480, PinholeIntrinsics{457.587, 456.134, 379.999, 255.238},
                                              std::vector<double>{-0.28368365, 0.07451284, -0.00010473, -3.55590700e-05});
  const auto T_b_c0 = from_rows({0.0148655429818, -0.999880929698, 0.00414029679422, -0.0216401454975,
                                 0.999557249008, 0.0149672133247, 0.025715529948, -0.064676986768,
                                 -0.0257744366974, 0.00375618835797, 0.999660727178, 0.00981073058949, 0, 0, 0, 1});
  const auto T_b_c1 = from_rows({0.0125552670891, -0.999755099723, 0.0182237714554, -0.0198435579556,
                                 0.999598781151, 0.0130119051815, 0.0251588363115, 0.0453689425024,
                                 -0.0253898008918, 0.0179005838253, 0.999517347078, 0.00786212447038, 0, 0, 0, 1});
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
