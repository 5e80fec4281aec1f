#include "pllvo/backend/pose_refiner.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>

#include "pllvo/common/error.h"
#include "pllvo/geometry/reprojection.h"
#include "pllvo/geometry/vanishing.h"

namespace pllvo::backend {

namespace {
using geometry::Matrix26d;
using geometry::Vector6d;
using Matrix6d = Eigen::Matrix<double, 6, 6>;
constexpr double kDegToRad = M_PI / 180.0;
// Cost charged for an observation that cannot be evaluated (behind the camera), as if its
// residual were this many pixels: keeps costs comparable when points cross the camera plane.
constexpr double kInvalidResidualPx = 100.0;
// A round stops when a step lowers the cost by less than this fraction, or moves less.
constexpr double kRelativeCostTolerance = 1e-6;
constexpr double kStepTolerance = 1e-10;

/// Inverse of the right Jacobian of SO(3).
Eigen::Matrix3d right_jacobian_inverse(const Eigen::Vector3d& phi) {
  const double theta = phi.norm();
  const Eigen::Matrix3d W = geometry::hat(phi);
  const double c = theta < 1e-6 ? 1.0 / 12.0
                                : 1.0 / (theta * theta) - (1.0 + std::cos(theta)) / (2.0 * theta * std::sin(theta));
  return Eigen::Matrix3d::Identity() + 0.5 * W + c * W * W;
}

/// Residuals and Jacobians of all observations for one pose of camera 0.
class Linearization {
 public:
  Linearization(const PoseRefinementProblem& problem, const PoseRefinerConfig& config)
      : problem_(problem), config_(config) {
    for (const auto& o : problem.points) check_camera(o.camera);
    for (const auto& o : problem.lines) check_camera(o.camera);
  }

  const Pose& extrinsic(int camera) const {
    return problem_.T_cam_cam0.empty() ? identity_ : problem_.T_cam_cam0[camera];
  }

  /// Residual (pixels) of point i; J: d r / d delta of T_cam0_world.
  bool point(const Pose& T_cam0_world, size_t i, Eigen::Vector2d& r, Matrix26d* J) const {
    const auto& o = problem_.points[i];
    const Pose& T_ck_c0 = extrinsic(o.camera);
    const Eigen::Vector3d p0 = T_cam0_world * o.p_world;
    Eigen::Vector2d xy;
    geometry::Matrix23d Jp;
    if (!geometry::project_normalised(T_ck_c0 * p0, xy, J ? &Jp : nullptr)) return false;
    const double s = problem_.focal_px * o.weight;
    r = s * (xy - o.xy);
    if (J) *J = s * Jp * T_ck_c0.linear() * geometry::point_jacobian_wrt_pose(p0);
    return true;
  }

  /// Residual (pixels, weighted) of line i: distances of both projected endpoints.
  bool line(const Pose& T_cam0_world, size_t i, Eigen::Vector2d& r, Matrix26d* J) const {
    const auto& o = problem_.lines[i];
    const Pose& T_ck_c0 = extrinsic(o.camera);
    const double s = problem_.focal_px * config_.line_weight;
    const Eigen::Vector3d* ends[2] = {&o.start_world, &o.end_world};
    for (int k = 0; k < 2; ++k) {
      const Eigen::Vector3d p0 = T_cam0_world * *ends[k];
      Eigen::RowVector3d Jd;
      if (!geometry::projected_point_line_distance(o.line, T_ck_c0 * p0, r[k], J ? &Jd : nullptr)) return false;
      r[k] *= s;
      if (J) J->row(k) = s * Jd * T_ck_c0.linear() * geometry::point_jacobian_wrt_pose(p0);
    }
    return true;
  }

  /// Vanishing-point error (pixels, weighted) of direction observation i; J (rotation
  /// columns only: a direction does not see the translation) by central differences.
  bool direction(const Pose& T_cam0_world, size_t i, double& r, Eigen::Matrix<double, 1, 6>* J) const {
    const Eigen::Matrix3d& R = T_cam0_world.linear();
    if (!direction_error(R, i, r)) return false;
    if (J) {
      constexpr double h = 1e-7;
      J->setZero();
      for (int k = 0; k < 3; ++k) {
        Eigen::Vector3d d = Eigen::Vector3d::Zero();
        d[k] = h;
        double rp = 0, rm = 0;
        if (!direction_error(geometry::so3_exp(d) * R, i, rp) || !direction_error(geometry::so3_exp(-d) * R, i, rm))
          return false;
        (*J)(0, 3 + k) = (rp - rm) / (2 * h);
      }
    }
    return true;
  }

  bool direction_error(const Eigen::Matrix3d& R_cam0_world, size_t i, double& r) const {
    const auto& o = problem_.directions[i];
    const auto e = geometry::vanishing_residual(R_cam0_world * o.direction_world, o.start, o.end);
    if (!e) return false;
    r = problem_.direction_weight * problem_.focal_px * *e;
    return true;
  }

  /// Prior residual (6) and its Jacobian; false when there is no prior to apply.
  bool prior(const Pose& T_cam0_world, Vector6d& r, Matrix6d* J) const {
    if (!config_.use_motion_prior || !problem_.predicted_T_world_cam) return false;
    const Pose& pred = *problem_.predicted_T_world_cam;
    const Eigen::Matrix3d R_wc = T_cam0_world.linear().transpose();
    const Eigen::Vector3d c = -R_wc * T_cam0_world.translation();
    const double st = config_.prior_sigma_position, sr = config_.prior_sigma_rotation_deg * kDegToRad;
    const Eigen::Vector3d e_rot = geometry::so3_log(pred.linear().transpose() * R_wc);
    r.head<3>() = (c - pred.translation()) / st;
    r.tail<3>() = e_rot / sr;
    if (J) {
      // The camera centre does not move under the rotation part of the left increment.
      J->setZero();
      J->topLeftCorner<3, 3>() = -R_wc / st;
      J->bottomRightCorner<3, 3>() = -right_jacobian_inverse(e_rot) / sr;
    }
    return true;
  }

  /// Robust cost of the active observations plus the prior.
  double cost(const Pose& T, const std::vector<uint8_t>& point_active, const std::vector<uint8_t>& line_active) const {
    double sum = 0;
    Eigen::Vector2d r;
    for (size_t i = 0; i < problem_.points.size(); ++i)
      if (point_active[i]) sum += config_.point_loss.rho(point(T, i, r, nullptr) ? r.squaredNorm() : invalid_s());
    for (size_t i = 0; i < problem_.lines.size(); ++i)
      if (line_active[i]) sum += config_.line_loss.rho(line(T, i, r, nullptr) ? r.squaredNorm() : invalid_s());
    double re = 0;
    for (size_t i = 0; i < problem_.directions.size(); ++i)
      if (direction(T, i, re, nullptr)) sum += config_.line_loss.rho(re * re);
    Vector6d rp;
    if (prior(T, rp, nullptr)) sum += rp.squaredNorm();
    return sum;
  }

  /// Reweighted normal equations H delta = -g at pose T.
  void normal_equations(const Pose& T, const std::vector<uint8_t>& point_active,
                        const std::vector<uint8_t>& line_active, Matrix6d& H, Vector6d& g) const {
    H.setZero();
    g.setZero();
    Eigen::Vector2d r;
    Matrix26d J;
    for (size_t i = 0; i < problem_.points.size(); ++i) {
      if (!point_active[i] || !point(T, i, r, &J)) continue;
      const double w = config_.point_loss.weight(r.squaredNorm());
      H.noalias() += w * J.transpose() * J;
      g.noalias() += w * J.transpose() * r;
    }
    for (size_t i = 0; i < problem_.lines.size(); ++i) {
      if (!line_active[i] || !line(T, i, r, &J)) continue;
      const double w = config_.line_loss.weight(r.squaredNorm());
      H.noalias() += w * J.transpose() * J;
      g.noalias() += w * J.transpose() * r;
    }
    double re = 0;
    Eigen::Matrix<double, 1, 6> Je;
    for (size_t i = 0; i < problem_.directions.size(); ++i) {
      if (!direction(T, i, re, &Je)) continue;
      const double w = config_.line_loss.weight(re * re);
      H.noalias() += w * Je.transpose() * Je;
      g.noalias() += w * Je.transpose() * re;
    }
    Vector6d rp;
    Matrix6d Jp;
    if (prior(T, rp, &Jp)) {
      H.noalias() += Jp.transpose() * Jp;
      g.noalias() += Jp.transpose() * rp;
    }
  }

  /// Inlier flags of all observations at pose T.
  void classify(const Pose& T, std::vector<uint8_t>& point_in, std::vector<uint8_t>& line_in) const {
    Eigen::Vector2d r;
    point_in.assign(problem_.points.size(), 0);
    line_in.assign(problem_.lines.size(), 0);
    for (size_t i = 0; i < point_in.size(); ++i)
      point_in[i] = point(T, i, r, nullptr) && r.norm() <= config_.point_outlier_threshold_px;
    for (size_t i = 0; i < line_in.size(); ++i)
      line_in[i] = line(T, i, r, nullptr) && r.norm() <= config_.line_outlier_threshold_px;
  }

  double rms(const Pose& T, const std::vector<uint8_t>& point_in, const std::vector<uint8_t>& line_in) const {
    double sum = 0;
    int n = 0;
    Eigen::Vector2d r;
    for (size_t i = 0; i < point_in.size(); ++i) {
      if (!point_in[i]) continue;
      sum += point(T, i, r, nullptr) ? r.squaredNorm() : invalid_s();
      ++n;
    }
    for (size_t i = 0; i < line_in.size(); ++i) {
      if (!line_in[i]) continue;
      sum += line(T, i, r, nullptr) ? r.squaredNorm() : invalid_s();
      ++n;
    }
    return n ? std::sqrt(sum / n) : 0.0;
  }

 private:
  static double invalid_s() { return kInvalidResidualPx * kInvalidResidualPx; }
  void check_camera(int camera) const {
    const int n = problem_.T_cam_cam0.empty() ? 1 : static_cast<int>(problem_.T_cam_cam0.size());
    if (camera < 0 || camera >= n)
      throw InternalError("PoseRefiner: observation of camera " + std::to_string(camera) + ", rig has " +
                          std::to_string(n));
  }

  const PoseRefinementProblem& problem_;
  const PoseRefinerConfig& config_;
  const Pose identity_ = Pose::Identity();
};
}  // namespace

void PoseRefinerConfig::load(const ConfigNode& node) {
  point_loss.load(node, "point_");
  line_loss.load(node, "line_");
  node.get("line_weight", line_weight);
  node.get("rounds", rounds);
  node.get("iterations_per_round", iterations_per_round);
  node.get("point_outlier_threshold_px", point_outlier_threshold_px);
  node.get("line_outlier_threshold_px", line_outlier_threshold_px);
  node.get("min_inliers", min_inliers);
  node.get("use_motion_prior", use_motion_prior);
  node.get("prior_sigma_position", prior_sigma_position);
  node.get("prior_sigma_rotation_deg", prior_sigma_rotation_deg);
  node.reject_unknown_keys();
}

PoseRefinementResult PoseRefiner::refine(const PoseRefinementProblem& problem) const {
  const Linearization lin(problem, config_);
  PoseRefinementResult out;
  const Pose T_initial = problem.T_world_cam.inverse();
  Pose T = T_initial;  // T_cam0_world
  std::vector<uint8_t> point_active(problem.points.size(), 1), line_active(problem.lines.size(), 1);

  for (int round = 0; round < std::max(1, config_.rounds); ++round) {
    double cost = lin.cost(T, point_active, line_active);
    double lambda = 1e-4;
    for (int it = 0; it < config_.iterations_per_round; ++it) {
      Matrix6d H;
      Vector6d g;
      lin.normal_equations(T, point_active, line_active, H, g);
      bool improved = false, converged = false;
      // Levenberg-Marquardt: raise the damping until a step lowers the cost.
      while (lambda < 1e10) {
        Matrix6d A = H;
        A.diagonal() += lambda * H.diagonal().cwiseMax(1e-9);
        const Vector6d delta = A.ldlt().solve(-g);
        if (!delta.allFinite()) break;
        const Pose candidate = geometry::apply_left_increment(delta, T);
        const double new_cost = lin.cost(candidate, point_active, line_active);
        if (new_cost < cost) {
          converged = cost - new_cost < kRelativeCostTolerance * cost || delta.norm() < kStepTolerance;
          T = candidate;
          cost = new_cost;
          lambda = std::max(1e-9, lambda * 0.1);
          improved = true;
          break;
        }
        lambda *= 10;
      }
      ++out.iterations;
      if (!improved || converged) break;
    }
    lin.classify(T, point_active, line_active);
  }

  out.point_inliers = point_active;
  out.line_inliers = line_active;
  out.num_point_inliers = static_cast<int>(std::count(point_active.begin(), point_active.end(), 1));
  out.num_line_inliers = static_cast<int>(std::count(line_active.begin(), line_active.end(), 1));
  out.initial_rms_px = lin.rms(T_initial, point_active, line_active);
  out.final_rms_px = lin.rms(T, point_active, line_active);
  out.T_world_cam = T.inverse();
  out.ok = T.matrix().allFinite() && out.num_point_inliers + out.num_line_inliers >= config_.min_inliers;
  return out;
}

}  // namespace pllvo::backend
