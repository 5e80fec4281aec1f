#pragma once

// The two-view motion refinement behind initialise_two_view and estimate_relative_motion: a
// bundle adjustment of (R, unit t) on the matches' Sampson errors, with optional pulls on the
// translation direction and on directions seen in both views.

#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace pllvo::geometry::two_view_detail {

/// Pulls a unit translation towards an expected direction: (t - t_expected) / sigma, in the
/// Sampson residuals' units (sigma_px per standard deviation).
struct DirectionPrior {
  Eigen::Vector3d expected;
  double scale;  ///< sigma_px / sigma (radians)

  template <typename T>
  bool operator()(const T* t, T* residual) const {
    for (int k = 0; k < 3; ++k) residual[k] = T(scale) * (t[k] - T(expected[k]));
    return true;
  }
};

/// A direction seen in both views: b (view 1) = R a (view 0); the residual is b x (R a), the
/// sine of their angle, scaled like DirectionPrior.
struct DirectionPairError {
  Eigen::Vector3d a, b;  ///< unit, signs aligned
  double scale;

  template <typename T>
  bool operator()(const T* q_xyzw, T* residual) const {
    const Eigen::Quaternion<T> q(q_xyzw[3], q_xyzw[0], q_xyzw[1], q_xyzw[2]);
    const Eigen::Matrix<T, 3, 1> Ra = q * a.cast<T>();
    const Eigen::Matrix<T, 3, 1> c = b.cast<T>().cross(Ra);
    for (int k = 0; k < 3; ++k) residual[k] = T(scale) * c[k];
    return true;
  }
};

/// Refines (R, unit t) on the inliers' Sampson errors: the RANSAC models come from minimal
/// samples and are noticeably off; this is a two-view bundle adjustment with the points
/// eliminated to first order. With `prior`, t is also pulled towards prior->expected; with
/// `pairs`, R is held by the directions seen in both views.
void refine_motion(Eigen::Matrix3d& R, Eigen::Vector3d& t, std::span<const Eigen::Vector2d> xy0,
                   std::span<const Eigen::Vector2d> xy1, const std::vector<uint8_t>& inliers, double focal_px,
                   double sigma_px, const DirectionPrior* prior = nullptr,
                   const std::vector<DirectionPairError>* pairs = nullptr);

/// Sampson distance (pixels) of one match under (R, t), outside Ceres.
double sampson_px(const Eigen::Matrix3d& R, const Eigen::Vector3d& t, const Eigen::Vector2d& x0,
                  const Eigen::Vector2d& x1, double focal_px);

}  // namespace pllvo::geometry::two_view_detail
