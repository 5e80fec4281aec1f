#include "pllvo/camera/stereo_rectifier.h"

#include <cmath>

#include <Eigen/Core>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgproc.hpp>

#include "pllvo/common/error.h"

namespace pllvo::camera {

namespace {
cv::Mat camera_matrix(const CameraModel& c) {
  cv::Mat K;
  cv::eigen2cv(c.intrinsics().K(), K);
  return K;
}

/// Every pixel maps onto itself: remap samples at 1/32 px, so offsets this small change no pixel.
bool is_identity_map(const cv::Mat& map_x, const cv::Mat& map_y) {
  constexpr float kTolerancePx = 1e-3f;
  for (int v = 0; v < map_x.rows; ++v) {
    const float* x = map_x.ptr<float>(v);
    const float* y = map_y.ptr<float>(v);
    for (int u = 0; u < map_x.cols; ++u)
      if (std::abs(x[u] - static_cast<float>(u)) > kTolerancePx || std::abs(y[u] - static_cast<float>(v)) > kTolerancePx)
        return false;
  }
  return true;
}
}  // namespace

StereoRectifier::StereoRectifier(CameraPtr cam0, CameraPtr cam1,
                                 const Eigen::Isometry3d& T_body_cam0,
                                 const Eigen::Isometry3d& T_body_cam1, double alpha)
    : cams_{std::move(cam0), std::move(cam1)} {
  if (cams_[0]->width() != cams_[1]->width() || cams_[0]->height() != cams_[1]->height())
    throw InputError("stereo: both cameras must have the same image size");
  size_ = cv::Size(cams_[0]->width(), cams_[0]->height());
  // cv::stereoRectify wants x1 = R x0 + T, i.e. T_cam1_cam0.
  const Eigen::Isometry3d T_c1_c0 = T_body_cam1.inverse() * T_body_cam0;
  if (T_c1_c0.translation().norm() < 1e-9) throw InputError("stereo: the baseline is zero");
  cv::Mat R, T, R0, R1, P0, P1, Q;
  cv::eigen2cv(Eigen::Matrix3d(T_c1_c0.linear()), R);
  cv::eigen2cv(Eigen::Vector3d(T_c1_c0.translation()), T);
  // Rectifying rotations depend only on the extrinsics; the distortion is handled by
  // our own remap below (which supports every model), so OpenCV sees zero distortion
  // and alpha is applied to an undistorted-equivalent pinhole pair.
  cv::stereoRectify(camera_matrix(*cams_[0]), cv::Mat(), camera_matrix(*cams_[1]), cv::Mat(),
                    size_, R, T, R0, R1, P0, P1, Q, cv::CALIB_ZERO_DISPARITY, alpha, size_);
  cv::cv2eigen(R0, R_[0]);
  cv::cv2eigen(R1, R_[1]);
  rect_.fx = P0.at<double>(0, 0);
  rect_.fy = P0.at<double>(1, 1);
  rect_.cx = P0.at<double>(0, 2);
  rect_.cy = P0.at<double>(1, 2);
  baseline_ = std::abs(P1.at<double>(0, 3) / P1.at<double>(0, 0));
  for (int i = 0; i < 2; ++i) {
    cams_[i]->undistort_rectify_map(rect_, size_, R_[i], map_x_[i], map_y_[i]);
    identity_[i] = is_identity_map(map_x_[i], map_y_[i]);
  }
}

Eigen::Isometry3d StereoRectifier::T_rect0_rect1() const {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(baseline_, 0, 0);
  return T;
}

cv::Mat StereoRectifier::rectify(int i, const cv::Mat& image) const {
  if (i < 0 || i > 1) throw InternalError("stereo camera index must be 0 or 1");
  if (image.size() != size_) throw InputError("stereo: image size does not match the calibration");
  if (identity_[i]) return image;  // already rectified (a synthetic pair, KITTI): ~3 ms a frame saved
  cv::Mat out;
  cv::remap(image, out, map_x_[i], map_y_[i], cv::INTER_LINEAR, cv::BORDER_CONSTANT);
  return out;
}

}  // namespace pllvo::camera
