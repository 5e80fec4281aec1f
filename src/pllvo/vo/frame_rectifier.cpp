#include "pllvo/vo/frame_rectifier.h"

#include <algorithm>

#include <opencv2/imgproc.hpp>

#include "pllvo/common/error.h"

namespace pllvo::vo {

camera::WorkingView parse_working_view(const std::string& name) {
  if (const auto view = camera::working_view_named(name)) return *view;
  throw InternalError("unknown working view '" + name + "'");
}

FrameRectifier::FrameRectifier(const io::Calibration& calibration, bool use_stereo, bool use_depth,
                               camera::WorkingView view)
    : calib_(calibration), use_depth_(use_depth && !use_stereo) {
  if (use_depth_ && !calibration.has_depth()) throw InputError("depth requested but the sequence has no depth images");
  if (!calibration.cam0) throw InputError("calibration has no camera");
  const auto& cam0 = *calibration.cam0;
  if (use_stereo) {
    if (!calibration.cam1) throw InputError("stereo requested but the calibration has one camera only");
    rectifier_ = std::make_unique<camera::StereoRectifier>(calibration.cam0, calibration.cam1,
                                                           calibration.T_body_cam0, calibration.T_body_cam1, view);
    const auto& k = rectifier_->rectified_intrinsics();
    camera_ = {k.fx, k.fy, k.cx, k.cy, rectifier_->view_size().width, rectifier_->view_size().height};
    T_cam0_work_ = geometry::make_pose(rectifier_->R_rect_cam(0).transpose(), Eigen::Vector3d::Zero());
    return;
  }
  const auto d = cam0.distortion();
  const bool distorted = std::any_of(d.begin(), d.end(), [](double v) { return v != 0.0; });
  const camera::PinholeView v =
      camera::working_view({&cam0}, {Eigen::Matrix3d::Identity()}, cam0.intrinsics(),
                           cv::Size(cam0.width(), cam0.height()), distorted ? view : camera::WorkingView::calibrated);
  camera_ = {v.K.fx, v.K.fy, v.K.cx, v.K.cy, v.size.width, v.size.height};
  if (distorted) cam0.undistort_rectify_map(v.K, v.size, Eigen::Matrix3d::Identity(), map_x_, map_y_);
}

double FrameRectifier::baseline() const { return rectifier_ ? rectifier_->baseline() : 0.0; }

cv::Mat FrameRectifier::to_gray(const cv::Mat& image, size_t index, const char* which, cv::Size expected) const {
  const std::string frame = "frame " + std::to_string(index) + " (" + which + ")";
  if (image.empty()) throw InputError(frame + ": no image");
  if (image.size() != expected)
    throw InputError(frame + ": image is " + std::to_string(image.cols) + "x" + std::to_string(image.rows) +
                     " but the calibration says " + std::to_string(expected.width) + "x" +
                     std::to_string(expected.height));
  cv::Mat gray;
  if (image.type() == CV_8UC1)
    gray = image;
  else if (image.type() == CV_8UC3)
    cv::cvtColor(image, gray, cv::COLOR_BGR2GRAY);
  else if (image.type() == CV_8UC4)
    cv::cvtColor(image, gray, cv::COLOR_BGRA2GRAY);
  else if (image.type() == CV_16UC1)
    image.convertTo(gray, CV_8U, 1.0 / 256.0);
  else
    throw InputError(frame + ": unsupported pixel type");
  return gray;
}

void FrameRectifier::apply(const io::Frame& frame, cv::Mat& left, cv::Mat& right, cv::Mat& depth) const {
  const auto& c0 = *calib_.cam0;
  const cv::Mat l = to_gray(frame.left, frame.index, "left", cv::Size(c0.width(), c0.height()));
  depth = cv::Mat();
  if (use_depth_ && !frame.depth.empty()) {  // type and size checked by OdometrySession::accept
    if (map_x_.empty())
      depth = frame.depth;
    else
      cv::remap(frame.depth, depth, map_x_, map_y_, cv::INTER_NEAREST, cv::BORDER_CONSTANT, cv::Scalar(0));
  }
  if (rectifier_) {
    const auto& c1 = *calib_.cam1;
    const cv::Mat r = to_gray(frame.right, frame.index, "right", cv::Size(c1.width(), c1.height()));
    left = rectifier_->rectify(0, l);
    right = rectifier_->rectify(1, r);
    return;
  }
  right = cv::Mat();
  if (map_x_.empty())
    left = l;
  else
    cv::remap(l, left, map_x_, map_y_, cv::INTER_LINEAR, cv::BORDER_CONSTANT);
}

}  // namespace pllvo::vo
