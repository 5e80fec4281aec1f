#include "pllvo/geometry/triangulation.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/SVD>

#include "pllvo/geometry/reprojection.h"

namespace pllvo::geometry {

namespace {
constexpr double kRadToDeg = 180.0 / M_PI;

Eigen::Vector3d ray(const Eigen::Vector2d& xy) { return Eigen::Vector3d(xy.x(), xy.y(), 1.0).normalized(); }

double total_error(std::span<const Pose> T_cam_world, std::span<const Eigen::Vector2d> xy,
                   const Eigen::Vector3d& p, bool& valid) {
  double sum = 0;
  valid = true;
  for (size_t i = 0; i < xy.size(); ++i) {
    Eigen::Vector2d e;
    if (!point_reprojection_error(T_cam_world[i], p, xy[i], e)) {
      valid = false;
      return 0;
    }
    sum += e.squaredNorm();
  }
  return sum;
}
}  // namespace

const char* to_string(TriangulationStatus status) {
  switch (status) {
    case TriangulationStatus::kOk: return "ok";
    case TriangulationStatus::kTooFewViews: return "too few views";
    case TriangulationStatus::kLowParallax: return "low parallax";
    case TriangulationStatus::kDegenerate: return "degenerate";
    case TriangulationStatus::kBehindCamera: return "behind camera";
    case TriangulationStatus::kTooFar: return "too far";
    case TriangulationStatus::kLargeError: return "large reprojection error";
  }
  return "?";
}

void PointTriangulationConfig::load(const ConfigNode& node) {
  node.get("min_parallax_deg", min_parallax_deg);
  node.get("max_reprojection_error_px", max_reprojection_error_px);
  node.get("min_depth", min_depth);
  node.get("max_depth", max_depth);
  node.get("refine_iterations", refine_iterations);
  node.reject_unknown_keys();
}

bool triangulate_linear(std::span<const Pose> T_cam_world, std::span<const Eigen::Vector2d> xy,
                        Eigen::Vector3d& p_world) {
  const int n = static_cast<int>(xy.size());
  if (n < 2 || T_cam_world.size() != xy.size()) return false;
  Eigen::MatrixXd A(2 * n, 4);
  for (int i = 0; i < n; ++i) {
    const Eigen::Matrix<double, 3, 4> P = T_cam_world[i].matrix().topRows<3>();
    A.row(2 * i) = xy[i].x() * P.row(2) - P.row(0);
    A.row(2 * i + 1) = xy[i].y() * P.row(2) - P.row(1);
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeFullV);
  const Eigen::Vector4d X = svd.matrixV().col(3);
  if (!(std::abs(X.w()) > 1e-12 * X.head<3>().norm())) return false;
  p_world = X.head<3>() / X.w();
  return p_world.allFinite();
}

void refine_point(std::span<const Pose> T_cam_world, std::span<const Eigen::Vector2d> xy,
                  int iterations, Eigen::Vector3d& p_world) {
  bool valid = false;
  double cost = total_error(T_cam_world, xy, p_world, valid);
  if (!valid) return;
  for (int it = 0; it < iterations; ++it) {
    Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
    Eigen::Vector3d g = Eigen::Vector3d::Zero();
    for (size_t i = 0; i < xy.size(); ++i) {
      Eigen::Vector2d e;
      PointErrorJacobians J;
      point_reprojection_error(T_cam_world[i], p_world, xy[i], e, &J);
      H += J.point.transpose() * J.point;
      g += J.point.transpose() * e;
    }
    const Eigen::Vector3d step = H.ldlt().solve(-g);
    if (!step.allFinite()) return;
    const Eigen::Vector3d candidate = p_world + step;
    const double new_cost = total_error(T_cam_world, xy, candidate, valid);
    if (!valid || new_cost >= cost) return;
    p_world = candidate;
    if (step.norm() < 1e-12 * (1.0 + p_world.norm())) return;
    cost = new_cost;
  }
}

double max_parallax_deg(std::span<const Pose> T_world_cam, std::span<const Eigen::Vector2d> xy) {
  std::vector<Eigen::Vector3d> rays(xy.size());
  for (size_t i = 0; i < xy.size(); ++i) rays[i] = T_world_cam[i].linear() * ray(xy[i]);
  double min_cos = 1.0;
  for (size_t i = 0; i < rays.size(); ++i)
    for (size_t j = i + 1; j < rays.size(); ++j) min_cos = std::min(min_cos, rays[i].dot(rays[j]));
  return std::acos(std::clamp(min_cos, -1.0, 1.0)) * kRadToDeg;
}

TriangulatedPoint triangulate_point(std::span<const Pose> T_world_cam,
                                    std::span<const Eigen::Vector2d> xy, double focal_px,
                                    const PointTriangulationConfig& config) {
  TriangulatedPoint out;
  if (xy.size() < 2 || T_world_cam.size() != xy.size()) return out;
  out.parallax_deg = max_parallax_deg(T_world_cam, xy);
  if (out.parallax_deg < config.min_parallax_deg) {
    out.status = TriangulationStatus::kLowParallax;
    return out;
  }
  std::vector<Pose> T_cam_world(T_world_cam.size());
  for (size_t i = 0; i < T_world_cam.size(); ++i) T_cam_world[i] = T_world_cam[i].inverse();
  if (!triangulate_linear(T_cam_world, xy, out.p_world)) {
    out.status = TriangulationStatus::kDegenerate;
    return out;
  }
  refine_point(T_cam_world, xy, config.refine_iterations, out.p_world);

  for (size_t i = 0; i < xy.size(); ++i) {
    const double depth = (T_cam_world[i] * out.p_world).z();
    if (!(depth >= config.min_depth)) {
      out.status = TriangulationStatus::kBehindCamera;
      return out;
    }
    if (config.max_depth > 0 && depth > config.max_depth) {
      out.status = TriangulationStatus::kTooFar;
      return out;
    }
    Eigen::Vector2d e;
    point_reprojection_error(T_cam_world[i], out.p_world, xy[i], e);
    out.max_error_px = std::max(out.max_error_px, e.norm() * focal_px);
  }
  out.status = out.max_error_px <= config.max_reprojection_error_px ? TriangulationStatus::kOk
                                                                     : TriangulationStatus::kLargeError;
  return out;
}

}  // namespace pllvo::geometry
