#pragma once
// Rectification of a calibrated stereo pair into two ideal pinhole views with
// parallel optical axes and horizontal epipolar lines (disparity along x only).
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "pllvo/camera/camera_model.h"

namespace pllvo::camera {

class StereoRectifier {
 public:
  /// `T_body_cam0/1`: each camera's pose in a common body frame (EuRoC's T_BS).
  /// `alpha` as in cv::stereoRectify: 0 keeps only valid pixels, 1 keeps all.
  StereoRectifier(CameraPtr cam0, CameraPtr cam1, const Eigen::Isometry3d& T_body_cam0,
                  const Eigen::Isometry3d& T_body_cam1, double alpha = 0.0);

  /// Intrinsics shared by both rectified views.
  const PinholeIntrinsics& rectified_intrinsics() const { return rect_; }
  double baseline() const { return baseline_; }  ///< metres, > 0
  /// Rotation from original camera i to rectified camera i.
  const Eigen::Matrix3d& R_rect_cam(int i) const { return R_[i]; }
  /// Pose of rectified camera 1 in rectified camera 0: a translation (baseline, 0, 0).
  Eigen::Isometry3d T_rect0_rect1() const;

  /// Rectifies one image of camera `i` (0 = left). An image that rectification leaves as it
  /// is (already rectified pair) comes back shared, not copied.
  cv::Mat rectify(int i, const cv::Mat& image) const;
  /// Rectification leaves camera `i`'s images as they are.
  bool is_identity(int i) const { return identity_[i]; }
  cv::Size size() const { return size_; }

 private:
  CameraPtr cams_[2];
  PinholeIntrinsics rect_;
  Eigen::Matrix3d R_[2];
  double baseline_ = 0;
  cv::Size size_;
  cv::Mat map_x_[2], map_y_[2];
  bool identity_[2] = {false, false};
};

}  // namespace pllvo::camera
