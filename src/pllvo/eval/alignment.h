#pragma once
// Alignment of an estimate onto a reference (Umeyama), as evo's PosePath3D.align and
// align_origin. The reference is never modified.
#include <string>
#include <string_view>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "pllvo/eval/pose_list.h"

namespace pllvo::eval {

enum class AlignMode {
  none,
  se3,         ///< rotation + translation (evo -a)
  sim3,        ///< rotation + translation + scale (evo -a -s)
  scale_only,  ///< only the Sim(3) scale is applied (evo -s)
};

AlignMode parse_align_mode(std::string_view name);  ///< none|se3|sim3|scale; InputError otherwise
std::string_view align_mode_name(AlignMode mode);   ///< as in the test vectors: se3, sim3, scale_only

/// y ~ scale * rotation * x + translation.
struct Similarity {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  double scale = 1.0;
};

/// Least-squares similarity from points x onto points y (3 x n each), Umeyama 1991 as evo
/// computes it; scale is 1 without `with_scale`. Throws EvalError(geometry) when fewer than
/// two singular values of the covariance exceed DBL_EPSILON. `allow_collinear` accepts one
/// (a straight-line reference, e.g. a camera on a linear slider, which evo refuses): the fit
/// is then still a least-squares minimiser, but the rotation about the line is arbitrary.
Similarity umeyama(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& y, bool with_scale,
                   bool allow_collinear = false);

struct Alignment {
  AlignMode applied = AlignMode::none;
  Similarity transform;  ///< for scale_only, rotation and translation are computed, not applied
  size_t n_used = 0;     ///< poses the fit used
};

/// Fits on the first `n_to_align` poses (all when negative) and applies the fit to every
/// estimate pose: p <- scale * p, then T <- [R t] * T (scale_only: only the first step).
Alignment align(PoseList& est, const PoseList& ref, AlignMode mode, long n_to_align = -1,
                bool allow_collinear = false);

/// T = ref[0] * est[0]^-1 applied to every estimate pose; returns T.
Eigen::Isometry3d align_origin(PoseList& est, const PoseList& ref);

}  // namespace pllvo::eval
