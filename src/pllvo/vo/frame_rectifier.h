#pragma once
// Turns raw frames into the ideal pinhole images the pipeline works on: undistorted for
// mono, rectified (horizontal epipolar lines) for stereo. Straight scene lines stay straight,
// which the line detector needs, and every later stage can use a plain pinhole model.
#include <memory>
#include <optional>
#include <string>

#include <opencv2/core.hpp>

#include "pllvo/camera/stereo_rectifier.h"
#include "pllvo/geometry/pose.h"
#include "pllvo/io/sequence.h"
#include "pllvo/vo/geometry_adapter.h"

namespace pllvo::vo {

/// "calibrated" | "whole" | "fit" (VoConfig's frontend.working_view); InternalError otherwise
/// (the config was validated).
camera::WorkingView parse_working_view(const std::string& name);

class FrameRectifier {
 public:
  /// `use_stereo`: rectify the pair (needs cam1); otherwise only cam0 is used. `use_depth`
  /// (without stereo): cam0's depth images are taken too (needs calibration.has_depth()).
  /// `view`: how much of a distorted image the working view keeps (camera::WorkingView).
  FrameRectifier(const io::Calibration& calibration, bool use_stereo, bool use_depth = false,
                 camera::WorkingView view = camera::WorkingView::calibrated);

  bool stereo() const { return rectifier_ != nullptr; }
  bool depth() const { return use_depth_; }  ///< RGB-D
  const Pinhole& camera() const { return camera_; }
  double baseline() const;  ///< metres, 0 for mono
  /// Pose of the working camera in cam0 (a rotation for stereo rectification, else identity).
  const geometry::Pose& T_cam0_work() const { return T_cam0_work_; }

  /// Working images of a frame. InputError naming the frame when an image is missing or its
  /// size differs from the calibration. Colour images are converted to grey. `depth` gets the
  /// working view's depth (CV_32F metres, nearest-pixel resampling: depth is not interpolated
  /// across edges) in RGB-D mode when the frame has one, else it is emptied.
  void apply(const io::Frame& frame, cv::Mat& left, cv::Mat& right, cv::Mat& depth) const;

 private:
  cv::Mat to_gray(const cv::Mat& image, size_t index, const char* which, cv::Size expected) const;

  const io::Calibration& calib_;
  std::unique_ptr<camera::StereoRectifier> rectifier_;
  bool use_depth_ = false;
  Pinhole camera_;
  geometry::Pose T_cam0_work_ = geometry::Pose::Identity();
  cv::Mat map_x_, map_y_;  ///< mono undistortion (empty when the camera has no distortion)
};

}  // namespace pllvo::vo
