#include "pllvo/vo/geometry_adapter.h"

#include <algorithm>
#include <cmath>

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

namespace pllvo::vo {
namespace {

cv::Mat cv_K(const Pinhole& cam) {
  return (cv::Mat_<double>(3, 3) << cam.fx, 0, cam.cx, 0, cam.fy, cam.cy, 0, 0, 1);
}

std::vector<cv::Point3d> to_cv(const std::vector<Eigen::Vector3d>& v) {
  std::vector<cv::Point3d> out;
  out.reserve(v.size());
  for (const auto& p : v) out.emplace_back(p.x(), p.y(), p.z());
  return out;
}

std::vector<cv::Point2d> to_cv(const std::vector<Eigen::Vector2d>& v) {
  std::vector<cv::Point2d> out;
  out.reserve(v.size());
  for (const auto& p : v) out.emplace_back(p.x(), p.y());
  return out;
}

geometry::Pose pose_from_rvec(const cv::Mat& rvec, const cv::Mat& tvec) {
  cv::Mat R;
  cv::Rodrigues(rvec, R);
  Eigen::Matrix3d Re;
  Eigen::Vector3d te;
  cv::cv2eigen(R, Re);
  cv::cv2eigen(tvec, te);
  return geometry::make_pose(Re, te);
}

void rvec_from_pose(const geometry::Pose& T, cv::Mat& rvec, cv::Mat& tvec) {
  cv::Mat R;
  cv::eigen2cv(Eigen::Matrix3d(T.linear()), R);
  cv::Rodrigues(R, rvec);
  cv::eigen2cv(Eigen::Vector3d(T.translation()), tvec);
}

/// Marks points reprojecting within `threshold` pixels.
int count_inliers(const Pinhole& cam, const geometry::Pose& T_cam_world, const std::vector<Eigen::Vector3d>& pts,
                  const std::vector<Eigen::Vector2d>& px, double threshold, std::vector<unsigned char>& inliers) {
  inliers.assign(pts.size(), 0);
  int n = 0;
  for (size_t i = 0; i < pts.size(); ++i) {
    Eigen::Vector2d uv;
    if (!cam.project(T_cam_world * pts[i], uv)) continue;
    if ((uv - px[i]).norm() <= threshold) inliers[i] = 1, ++n;
  }
  return n;
}

double ray_angle_deg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180.0 / M_PI;
}

}  // namespace

Eigen::Matrix3d Pinhole::K() const {
  Eigen::Matrix3d k;
  k << fx, 0, cx, 0, fy, cy, 0, 0, 1;
  return k;
}

bool Pinhole::project(const Eigen::Vector3d& p, Eigen::Vector2d& px) const {
  if (!(p.z() > 1e-6)) return false;
  px = {fx * p.x() / p.z() + cx, fy * p.y() / p.z() + cy};
  return true;
}

Eigen::Vector3d Pinhole::ray(const Eigen::Vector2d& px) const {
  return {(px.x() - cx) / fx, (px.y() - cy) / fy, 1.0};
}

bool Pinhole::inside(const Eigen::Vector2d& px, double border) const {
  return px.x() >= border && px.y() >= border && px.x() <= width - 1 - border && px.y() <= height - 1 - border;
}

// INTERIM (until geometry/ lands): cv::solvePnPRansac + cv::solvePnPRefineLM.
PoseEstimate estimate_pose_ransac(const Pinhole& cam, const std::vector<Eigen::Vector3d>& points_world,
                                  const std::vector<Eigen::Vector2d>& pixels, const geometry::Pose* guess,
                                  const PoseConfig& config) {
  PoseEstimate est;
  if (points_world.size() < 6 || points_world.size() != pixels.size()) return est;
  cv::Mat rvec, tvec;
  if (guess) rvec_from_pose(*guess, rvec, tvec);
  std::vector<int> inlier_idx;
  const bool ok = cv::solvePnPRansac(to_cv(points_world), to_cv(pixels), cv_K(cam), cv::noArray(), rvec, tvec,
                                     guess != nullptr, config.ransac_iterations,
                                     static_cast<float>(config.ransac_threshold_px), config.ransac_confidence,
                                     inlier_idx, cv::SOLVEPNP_ITERATIVE);
  if (!ok || static_cast<int>(inlier_idx.size()) < config.min_inliers) return est;
  est.T_cam_world = pose_from_rvec(rvec, tvec);
  est.num_inliers = count_inliers(cam, est.T_cam_world, points_world, pixels, config.ransac_threshold_px, est.inliers);
  est.ok = est.num_inliers >= config.min_inliers;
  return est;
}

// INTERIM (until backend/ lands): points only, Levenberg-Marquardt without robust loss.
PoseEstimate refine_pose(const Pinhole& cam, const geometry::Pose& T_cam_world,
                         const std::vector<Eigen::Vector3d>& points_world, const std::vector<Eigen::Vector2d>& pixels,
                         const std::vector<unsigned char>& use, const std::vector<LineMeasurement>& /*lines*/,
                         const PoseConfig& config) {
  PoseEstimate est;
  std::vector<Eigen::Vector3d> pts;
  std::vector<Eigen::Vector2d> px;
  for (size_t i = 0; i < points_world.size(); ++i)
    if (use[i]) pts.push_back(points_world[i]), px.push_back(pixels[i]);
  est.T_cam_world = T_cam_world;
  if (pts.size() >= 4) {
    cv::Mat rvec, tvec;
    rvec_from_pose(T_cam_world, rvec, tvec);
    cv::solvePnPRefineLM(to_cv(pts), to_cv(px), cv_K(cam), cv::noArray(), rvec, tvec);
    est.T_cam_world = pose_from_rvec(rvec, tvec);
  }
  est.num_inliers = count_inliers(cam, est.T_cam_world, points_world, pixels, config.ransac_threshold_px, est.inliers);
  est.ok = est.num_inliers >= config.min_inliers;
  return est;
}

// INTERIM (until geometry/ lands): essential matrix only; a homography-dominated pair
// (planar scene or too little translation) is refused, so initialisation waits for motion.
TwoViewResult initialize_two_view(const Pinhole& cam, const std::vector<Eigen::Vector2d>& px0,
                                  const std::vector<Eigen::Vector2d>& px1, const InitConfig& config) {
  TwoViewResult r;
  if (px0.size() < 8 || px0.size() != px1.size()) return r;
  const auto p0 = to_cv(px0), p1 = to_cv(px1);
  cv::Mat maskE, maskH;
  cv::Mat E = cv::findEssentialMat(p0, p1, cv_K(cam), cv::RANSAC, 0.999, 1.0, maskE);
  cv::Mat H = cv::findHomography(p0, p1, cv::RANSAC, 2.0, maskH);
  if (E.empty() || E.rows != 3) return r;
  const int inE = cv::countNonZero(maskE), inH = H.empty() ? 0 : cv::countNonZero(maskH);
  r.model = inH > 0.9 * inE ? "homography" : "essential";
  if (r.model == "homography") return r;
  cv::Mat R, t, tri;
  cv::recoverPose(E, p0, p1, cv_K(cam), R, t, 1e3, maskE, tri);
  Eigen::Matrix3d Re;
  Eigen::Vector3d te;
  cv::cv2eigen(R, Re);
  cv::cv2eigen(t, te);
  r.T_1_0 = geometry::make_pose(Re, te.normalized());
  r.points_0.assign(px0.size(), Eigen::Vector3d::Zero());
  r.valid.assign(px0.size(), 0);
  std::vector<double> parallax;
  const Eigen::Vector3d c1_in_0 = r.T_1_0.inverse().translation();
  for (size_t i = 0; i < px0.size(); ++i) {
    if (!maskE.at<unsigned char>(static_cast<int>(i))) continue;
    const double w = tri.at<double>(3, static_cast<int>(i));
    if (std::abs(w) < 1e-12) continue;
    const Eigen::Vector3d X(tri.at<double>(0, i) / w, tri.at<double>(1, i) / w, tri.at<double>(2, i) / w);
    const Eigen::Vector3d X1 = r.T_1_0 * X;
    Eigen::Vector2d uv0, uv1;
    if (!cam.project(X, uv0) || !cam.project(X1, uv1)) continue;
    if ((uv0 - px0[i]).norm() > 2.0 || (uv1 - px1[i]).norm() > 2.0) continue;
    const double angle = ray_angle_deg(X, X - c1_in_0);
    if (angle < 0.25 * config.mono_min_parallax_deg) continue;
    r.points_0[i] = X;
    r.valid[i] = 1;
    parallax.push_back(angle);
  }
  if (static_cast<int>(parallax.size()) < config.min_points / 2) return r;
  std::nth_element(parallax.begin(), parallax.begin() + parallax.size() / 2, parallax.end());
  r.median_parallax_deg = parallax[parallax.size() / 2];
  r.ok = r.median_parallax_deg >= config.mono_min_parallax_deg;
  return r;
}

// INTERIM (until geometry/ lands): cv::triangulatePoints on normalised coordinates.
std::optional<Eigen::Vector3d> triangulate_point(const Pinhole& cam, const geometry::Pose& T_world_c0,
                                                 const geometry::Pose& T_world_c1, const Eigen::Vector2d& px0,
                                                 const Eigen::Vector2d& px1, const MappingConfig& config) {
  const geometry::Pose T0 = T_world_c0.inverse(), T1 = T_world_c1.inverse();
  const Eigen::Vector3d r0 = T_world_c0.linear() * cam.ray(px0), r1 = T_world_c1.linear() * cam.ray(px1);
  if (ray_angle_deg(r0, r1) < config.min_parallax_deg) return std::nullopt;
  cv::Mat P0, P1;
  cv::eigen2cv(Eigen::Matrix<double, 3, 4>(T0.matrix().topRows<3>()), P0);
  cv::eigen2cv(Eigen::Matrix<double, 3, 4>(T1.matrix().topRows<3>()), P1);
  const Eigen::Vector3d n0 = cam.ray(px0), n1 = cam.ray(px1);
  cv::Mat x0 = (cv::Mat_<double>(2, 1) << n0.x(), n0.y()), x1 = (cv::Mat_<double>(2, 1) << n1.x(), n1.y());
  cv::Mat X;
  cv::triangulatePoints(P0, P1, x0, x1, X);
  const double w = X.at<double>(3);
  if (std::abs(w) < 1e-12) return std::nullopt;
  const Eigen::Vector3d Xw(X.at<double>(0) / w, X.at<double>(1) / w, X.at<double>(2) / w);
  const Eigen::Vector3d c0 = T0 * Xw, c1 = T1 * Xw;
  for (const auto& [pc, px] : {std::pair{c0, px0}, std::pair{c1, px1}}) {
    if (pc.z() < config.min_depth_m || pc.z() > config.max_depth_m) return std::nullopt;
    Eigen::Vector2d uv;
    if (!cam.project(pc, uv) || (uv - px).norm() > config.max_reprojection_px) return std::nullopt;
  }
  return Xw;
}

std::optional<Eigen::Vector3d> triangulate_stereo(const Pinhole& cam, double baseline, const Eigen::Vector2d& left,
                                                  const Eigen::Vector2d& right, double min_depth, double max_depth) {
  const double disparity = left.x() - right.x();
  if (disparity <= 0) return std::nullopt;
  const double z = cam.fx * baseline / disparity;
  if (z < min_depth || z > max_depth) return std::nullopt;
  return Eigen::Vector3d((left.x() - cam.cx) * z / cam.fx, (left.y() - cam.cy) * z / cam.fy, z);
}

// INTERIM (until backend/ lands): no optimisation.
int bundle_adjust_window(MapData& /*map*/, const Pinhole& /*cam*/, const std::vector<Id>& /*window*/,
                         int /*fixed*/, const MappingConfig& /*config*/) {
  return 0;
}

}  // namespace pllvo::vo
