#include "pllvo/eval/alignment.h"

#include <algorithm>
#include <limits>

#include <Eigen/SVD>

#include "pllvo/common/error.h"
#include "pllvo/eval/eval_error.h"

namespace pllvo::eval {

AlignMode parse_align_mode(std::string_view name) {
  if (name == "none") return AlignMode::none;
  if (name == "se3") return AlignMode::se3;
  if (name == "sim3") return AlignMode::sim3;
  if (name == "scale" || name == "scale_only") return AlignMode::scale_only;
  throw InputError("unknown alignment '" + std::string(name) + "' (use none, se3, sim3 or scale)");
}

std::string_view align_mode_name(AlignMode mode) {
  switch (mode) {
    case AlignMode::none: return "none";
    case AlignMode::se3: return "se3";
    case AlignMode::sim3: return "sim3";
    case AlignMode::scale_only: return "scale_only";
  }
  return "none";
}

Similarity umeyama(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& y, bool with_scale, bool allow_collinear) {
  if (x.cols() != y.cols() || x.cols() == 0)
    throw EvalError(EvalErrorKind::geometry, "data matrices must have the same, non-zero number of points");
  const double n = static_cast<double>(x.cols());
  const Eigen::Vector3d mean_x = x.rowwise().mean();
  const Eigen::Vector3d mean_y = y.rowwise().mean();
  const Eigen::Matrix3Xd xc = x.colwise() - mean_x;
  const Eigen::Matrix3Xd yc = y.colwise() - mean_y;
  const double sigma_x = xc.squaredNorm() / n;
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (Eigen::Index i = 0; i < x.cols(); ++i) cov += yc.col(i) * xc.col(i).transpose();
  cov *= 1.0 / n;

  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(cov, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Vector3d d = svd.singularValues();
  const int rank = static_cast<int>((d.array() > std::numeric_limits<double>::epsilon()).count());
  if (rank < (allow_collinear ? 1 : 2))
    throw EvalError(EvalErrorKind::geometry, "Degenerate covariance rank, Umeyama alignment is not possible");

  Eigen::Matrix3d S = Eigen::Matrix3d::Identity();
  if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0.0) S(2, 2) = -1.0;
  Similarity out;
  out.rotation = svd.matrixU() * S * svd.matrixV().transpose();
  out.scale = with_scale ? (d.asDiagonal() * S).trace() / sigma_x : 1.0;
  out.translation = mean_y - out.scale * (out.rotation * mean_x);
  return out;
}

Alignment align(PoseList& est, const PoseList& ref, AlignMode mode, long n_to_align, bool allow_collinear) {
  if (mode == AlignMode::none) throw InternalError("align: mode none");
  if (est.size() != ref.size()) throw InternalError("align: trajectories must have the same number of poses");
  if (n_to_align == 0) throw InputError("--n-to-align must be positive (or -1 for all poses)");
  const size_t n = n_to_align < 0 ? est.size() : std::min(est.size(), static_cast<size_t>(n_to_align));
  Eigen::Matrix3Xd x(3, n), y(3, n);
  for (size_t i = 0; i < n; ++i) {
    x.col(i) = est[i].translation();
    y.col(i) = ref[i].translation();
  }
  Alignment out;
  out.applied = mode;
  out.n_used = n;
  // Scale-only uses the scale of the full (rotation-aware) Sim(3) fit, as evo does.
  out.transform = umeyama(x, y, mode != AlignMode::se3, allow_collinear);

  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = out.transform.rotation;
  T.translation() = out.transform.translation;
  for (auto& pose : est) {
    if (mode != AlignMode::se3) pose.translation() *= out.transform.scale;
    if (mode != AlignMode::scale_only) pose = T * pose;
  }
  return out;
}

Eigen::Isometry3d align_origin(PoseList& est, const PoseList& ref) {
  if (est.empty() || ref.empty()) throw InternalError("align_origin: empty trajectory");
  const Eigen::Isometry3d T = ref.front() * est.front().inverse();
  for (auto& pose : est) pose = T * pose;
  return T;
}

}  // namespace pllvo::eval
