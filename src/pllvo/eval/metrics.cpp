#include "pllvo/eval/metrics.h"

#include <array>
#include <numbers>
#include <string>

#include "pllvo/common/error.h"
#include "pllvo/eval/eval_error.h"
#include "pllvo/geometry/pose.h"

namespace pllvo::eval {

namespace {

constexpr std::array<std::pair<PoseRelation, std::string_view>, 7> kNames{{
    {PoseRelation::trans_part, "trans_part"},
    {PoseRelation::rot_part, "rot_part"},
    {PoseRelation::full, "full"},
    {PoseRelation::angle_deg, "angle_deg"},
    {PoseRelation::angle_rad, "angle_rad"},
    {PoseRelation::point_distance, "point_distance"},
    {PoseRelation::point_distance_error_ratio, "point_distance_error_ratio"},
}};

/// Error of one SE(3) error pose E (identity when estimate and reference agree).
double pose_error(const Eigen::Isometry3d& E, PoseRelation relation) {
  switch (relation) {
    case PoseRelation::trans_part: return E.translation().norm();
    case PoseRelation::rot_part: return (E.linear() - Eigen::Matrix3d::Identity()).norm();
    case PoseRelation::full: return (E.matrix() - Eigen::Matrix4d::Identity()).norm();
    case PoseRelation::angle_rad: return geometry::rotation_angle(E.linear());
    case PoseRelation::angle_deg: return geometry::rotation_angle(E.linear()) * (180.0 / std::numbers::pi);
    default: throw InternalError("pose_error: relation without an error pose");
  }
}

void check_sizes(const PoseList& ref, const PoseList& est) {
  if (ref.size() != est.size())
    throw EvalError(EvalErrorKind::metrics, "trajectories must have same number of poses");
}

}  // namespace

PoseRelation parse_pose_relation(std::string_view name) {
  for (const auto& [relation, n] : kNames)
    if (n == name) return relation;
  std::string valid;
  for (const auto& [relation, n] : kNames) valid += (valid.empty() ? "" : ", ") + std::string(n);
  throw InputError("unknown pose relation '" + std::string(name) + "' (use " + valid + ")");
}

std::string_view pose_relation_name(PoseRelation relation) {
  for (const auto& [r, n] : kNames)
    if (r == relation) return n;
  return "?";
}

std::string_view unit_name(PoseRelation relation) {
  switch (relation) {
    case PoseRelation::trans_part:
    case PoseRelation::point_distance: return "m";
    case PoseRelation::angle_deg: return "deg";
    case PoseRelation::angle_rad: return "rad";
    case PoseRelation::point_distance_error_ratio: return "%";
    default: return "unit-less";
  }
}

std::vector<double> ape_errors(const PoseList& ref, const PoseList& est, PoseRelation relation) {
  check_sizes(ref, est);
  if (relation == PoseRelation::point_distance_error_ratio)
    throw EvalError(EvalErrorKind::metrics, "unsupported pose_relation for APE: point_distance_error_ratio");
  std::vector<double> errors;
  errors.reserve(ref.size());
  for (size_t i = 0; i < ref.size(); ++i) {
    if (relation == PoseRelation::trans_part || relation == PoseRelation::point_distance)
      errors.push_back((est[i].translation() - ref[i].translation()).norm());
    else
      errors.push_back(pose_error(est[i].inverse() * ref[i], relation));
  }
  return errors;
}

std::vector<double> rpe_errors(const PoseList& ref, const PoseList& est, const IdPairs& pairs,
                               PoseRelation relation) {
  check_sizes(ref, est);
  std::vector<double> errors;
  errors.reserve(pairs.size());
  for (const auto& [i, j] : pairs) {
    if (relation == PoseRelation::point_distance || relation == PoseRelation::point_distance_error_ratio) {
      const double d_ref = (ref[i].translation() - ref[j].translation()).norm();
      const double d_est = (est[i].translation() - est[j].translation()).norm();
      const double diff = std::abs(d_ref - d_est);
      if (relation == PoseRelation::point_distance) errors.push_back(diff);
      else if (d_ref != 0.0) errors.push_back(diff / d_ref * 100.0);
      continue;
    }
    const Eigen::Isometry3d ref_rel = ref[i].inverse() * ref[j];
    const Eigen::Isometry3d est_rel = est[i].inverse() * est[j];
    errors.push_back(pose_error(ref_rel.inverse() * est_rel, relation));
  }
  return errors;
}

}  // namespace pllvo::eval
