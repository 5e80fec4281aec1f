#include "pllvo/geometry/pnp.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include "pllvo/geometry/config_choice.h"
#include "pllvo/geometry/reprojection.h"

namespace pllvo::geometry {

namespace {
const Choices<PnpMethod> kMethodChoices = {{"ap3p", PnpMethod::kAp3p},
                                           {"p3p", PnpMethod::kP3p},
                                           {"epnp", PnpMethod::kEpnp},
                                           {"sqpnp", PnpMethod::kSqpnp}};

int opencv_flag(PnpMethod m) {
  switch (m) {
    case PnpMethod::kAp3p: return cv::SOLVEPNP_AP3P;
    case PnpMethod::kP3p: return cv::SOLVEPNP_P3P;
    case PnpMethod::kEpnp: return cv::SOLVEPNP_EPNP;
    case PnpMethod::kSqpnp: return cv::SOLVEPNP_SQPNP;
  }
  return cv::SOLVEPNP_EPNP;
}

Pose pose_from_rvec_tvec(const cv::Mat& rvec, const cv::Mat& tvec) {
  cv::Mat R_cv;
  cv::Rodrigues(rvec, R_cv);
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
  cv::cv2eigen(R_cv, R);
  cv::cv2eigen(tvec, t);
  return make_pose(R, t);
}

int classify(const Pose& T_cam_world, std::span<const Eigen::Vector3d> points,
             std::span<const Eigen::Vector2d> xy, double threshold, std::vector<uint8_t>& inliers) {
  inliers.assign(xy.size(), 0);
  int n = 0;
  for (size_t i = 0; i < xy.size(); ++i) {
    Eigen::Vector2d e;
    if (point_reprojection_error(T_cam_world, points[i], xy[i], e) && e.norm() <= threshold) {
      inliers[i] = 1;
      ++n;
    }
  }
  return n;
}
}  // namespace

void PnpConfig::load(const ConfigNode& node) {
  get_choice(node, "method", method, kMethodChoices);
  node.get("reprojection_threshold_px", reprojection_threshold_px);
  node.get("confidence", confidence);
  node.get("max_iterations", max_iterations);
  node.get("min_inliers", min_inliers);
  node.get("refine", refine);
  node.reject_unknown_keys();
}

PnpResult solve_pnp_ransac(std::span<const Eigen::Vector3d> points_world,
                           std::span<const Eigen::Vector2d> xy, double focal_px,
                           const PnpConfig& config) {
  PnpResult out;
  out.inliers.assign(xy.size(), 0);
  const int n = static_cast<int>(xy.size());
  if (n != static_cast<int>(points_world.size()) || n < std::max(4, config.min_inliers)) return out;

  std::vector<cv::Point3d> obj(n);
  std::vector<cv::Point2d> img(n);
  for (int i = 0; i < n; ++i) {
    obj[i] = {points_world[i].x(), points_world[i].y(), points_world[i].z()};
    img[i] = {xy[i].x(), xy[i].y()};
  }
  const double threshold = config.reprojection_threshold_px / focal_px;
  const cv::Mat K = cv::Mat::eye(3, 3, CV_64F);
  cv::Mat rvec, tvec;
  std::vector<int> inlier_idx;
  bool found = false;
  try {
    found = cv::solvePnPRansac(obj, img, K, cv::noArray(), rvec, tvec, false, config.max_iterations,
                               static_cast<float>(threshold), config.confidence, inlier_idx,
                               opencv_flag(config.method));
  } catch (const cv::Exception&) {
    found = false;  // OpenCV throws on degenerate samples (e.g. all points collinear)
  }
  if (!found || static_cast<int>(inlier_idx.size()) < std::max(4, config.min_inliers)) return out;

  if (config.refine) {
    std::vector<cv::Point3d> obj_in;
    std::vector<cv::Point2d> img_in;
    for (int i : inlier_idx) obj_in.push_back(obj[i]), img_in.push_back(img[i]);
    cv::solvePnPRefineLM(obj_in, img_in, K, cv::noArray(), rvec, tvec);
  }
  const Pose T_cam_world = pose_from_rvec_tvec(rvec, tvec);
  if (!T_cam_world.matrix().allFinite()) return out;
  out.num_inliers = classify(T_cam_world, points_world, xy, threshold, out.inliers);
  out.T_world_cam = T_cam_world.inverse();
  out.ok = out.num_inliers >= config.min_inliers;
  return out;
}

}  // namespace pllvo::geometry
