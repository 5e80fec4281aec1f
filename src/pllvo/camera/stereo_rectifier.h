#pragma once
// Rectification of a calibrated stereo pair into two ideal pinhole views with
// parallel optical axes and horizontal epipolar lines (disparity along x only).
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "pllvo/camera/camera_model.h"

namespace pllvo::camera {

/// What the working (ideal pinhole) view keeps of a distorted camera's image. EuRoC's barrel
/// distortion (k1 = -0.28) pulls the raw image's sides outwards: at the calibrated focal lengths
/// and image size the undistorted view loses ~15 % of the raw width.
enum class WorkingView {
  calibrated,  ///< the calibration's focal lengths and image size: the sides are cropped
  whole,       ///< the calibration's focal lengths, the image enlarged to span the raw image side to side
  fit,         ///< the image size kept, the focal lengths shrunk until it spans the raw image
};

/// "calibrated" | "whole" | "fit"; nothing for any other name.
std::optional<WorkingView> working_view_named(const std::string& name);

struct PinholeView {
  PinholeIntrinsics K;
  cv::Size size;
};

/// The working view of cameras i (rotated into it by R_view_cam[i]; both images of a stereo pair
/// give one view): under `whole` and `fit`, the largest view that shows raw pixels of every
/// camera only and reaches each raw side. A lens that crops nothing keeps `calibrated` and `size`.
PinholeView working_view(const std::vector<const CameraModel*>& cameras, const std::vector<Eigen::Matrix3d>& R_view_cam,
                         const PinholeIntrinsics& calibrated, cv::Size size, WorkingView view);

class StereoRectifier {
 public:
  /// `T_body_cam0/1`: each camera's pose in a common body frame (EuRoC's T_BS).
  /// `view`: calibrated keeps cv::stereoRectify's focal length and the image size (alpha 0 on the
  /// distortion-free pair); whole and fit make the rectified views span both raw images (working_view).
  StereoRectifier(CameraPtr cam0, CameraPtr cam1, const Eigen::Isometry3d& T_body_cam0,
                  const Eigen::Isometry3d& T_body_cam1, WorkingView view = WorkingView::calibrated);

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
  cv::Size size() const { return size_; }  ///< of the raw images
  cv::Size view_size() const { return view_size_; }  ///< of the rectified images

 private:
  CameraPtr cams_[2];
  PinholeIntrinsics rect_;
  Eigen::Matrix3d R_[2];
  double baseline_ = 0;
  cv::Size size_, view_size_;
  cv::Mat map_x_[2], map_y_[2];
  bool identity_[2] = {false, false};
};

}  // namespace pllvo::camera
