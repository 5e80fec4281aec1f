#include "pllvo/camera/stereo_rectifier.h"

#include <algorithm>
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

std::optional<WorkingView> working_view_named(const std::string& name) {
  if (name == "calibrated") return WorkingView::calibrated;
  if (name == "whole") return WorkingView::whole;
  if (name == "fit") return WorkingView::fit;
  return std::nullopt;
}

PinholeView working_view(const std::vector<const CameraModel*>& cameras, const std::vector<Eigen::Matrix3d>& R_view_cam,
                         const PinholeIntrinsics& calibrated, cv::Size size, WorkingView view) {
  if (view == WorkingView::calibrated) return {calibrated, size};
  // Normalised bounds of the view: the innermost point of each raw side, so the view holds raw
  // pixels only (barrel distortion bows the undistorted sides inwards, between the corners).
  double left = -1e9, right = 1e9, top = -1e9, bottom = 1e9;
  constexpr int kSamples = 64;
  for (size_t c = 0; c < cameras.size(); ++c) {
    const CameraModel& cam = *cameras[c];
    const double w = cam.width() - 1.0, h = cam.height() - 1.0;
    auto normalised = [&](double u, double v, Eigen::Vector2d& xy) {
      Eigen::Vector3d b;
      if (!cam.unproject({u, v}, b)) return false;
      b = R_view_cam[c] * b;
      if (b.z() <= 1e-6) return false;
      xy = b.head<2>() / b.z();
      return true;
    };
    for (int i = 0; i <= kSamples; ++i) {
      const double t = static_cast<double>(i) / kSamples;
      Eigen::Vector2d xy;
      if (normalised(0, t * h, xy)) left = std::max(left, xy.x());
      if (normalised(w, t * h, xy)) right = std::min(right, xy.x());
      if (normalised(t * w, 0, xy)) top = std::max(top, xy.y());
      if (normalised(t * w, h, xy)) bottom = std::min(bottom, xy.y());
    }
  }
  if (!(right > left && bottom > top)) throw InputError("working view: the cameras' undistorted images do not overlap");
  // Pixels the calibrated focal lengths need to span the bounds; within the image: nothing cropped.
  const double span_x = (right - left) * calibrated.fx, span_y = (bottom - top) * calibrated.fy;
  if (span_x <= size.width - 1.0 + 1e-6 && span_y <= size.height - 1.0 + 1e-6) return {calibrated, size};
  PinholeView out{calibrated, size};
  if (view == WorkingView::whole) {  // focal lengths kept, the image grows
    out.size = cv::Size(std::max(size.width, static_cast<int>(std::floor(span_x)) + 1),
                        std::max(size.height, static_cast<int>(std::floor(span_y)) + 1));
  } else {  // WorkingView::fit: the image keeps its size, the focal lengths shrink
    out.K.fx = std::min(calibrated.fx, (size.width - 1.0) / (right - left));
    out.K.fy = std::min(calibrated.fy, (size.height - 1.0) / (bottom - top));
  }
  // The view centred on the bounds.
  out.K.cx = 0.5 * (out.size.width - 1.0) - out.K.fx * 0.5 * (left + right);
  out.K.cy = 0.5 * (out.size.height - 1.0) - out.K.fy * 0.5 * (top + bottom);
  return out;
}

StereoRectifier::StereoRectifier(CameraPtr cam0, CameraPtr cam1,
                                 const Eigen::Isometry3d& T_body_cam0,
                                 const Eigen::Isometry3d& T_body_cam1, WorkingView view)
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
  // our own remap below (which supports every model), so OpenCV sees zero distortion;
  // working_view then sets how much of the distorted images the rectified views keep.
  cv::stereoRectify(camera_matrix(*cams_[0]), cv::Mat(), camera_matrix(*cams_[1]), cv::Mat(),
                    size_, R, T, R0, R1, P0, P1, Q, cv::CALIB_ZERO_DISPARITY, 0.0, size_);
  cv::cv2eigen(R0, R_[0]);
  cv::cv2eigen(R1, R_[1]);
  rect_.fx = P0.at<double>(0, 0);
  rect_.fy = P0.at<double>(1, 1);
  rect_.cx = P0.at<double>(0, 2);
  rect_.cy = P0.at<double>(1, 2);
  baseline_ = std::abs(P1.at<double>(0, 3) / P1.at<double>(0, 0));
  // One row of both views stays one epipolar line: both share these intrinsics.
  const PinholeView v = working_view({cams_[0].get(), cams_[1].get()}, {R_[0], R_[1]}, rect_, size_, view);
  rect_ = v.K;
  view_size_ = v.size;
  for (int i = 0; i < 2; ++i) {
    cams_[i]->undistort_rectify_map(rect_, view_size_, R_[i], map_x_[i], map_y_[i]);
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
