#include "pllvo/eval/pair_selection.h"

#include <cmath>
#include <numbers>
#include <string>

#include "pllvo/common/error.h"
#include "pllvo/eval/eval_error.h"
#include "pllvo/eval/nearest_index.h"
#include "pllvo/geometry/pose.h"

namespace pllvo::eval {

namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

IdPairs pairs_by_index(size_t n, size_t delta, bool all_pairs) {
  IdPairs out;
  if (all_pairs) {
    for (size_t i = 0; i + delta < n; ++i) out.emplace_back(i, i + delta);
  } else {
    for (size_t i = 0; i + delta < n; i += delta) out.emplace_back(i, i + delta);
  }
  return out;
}

IdPairs consecutive(const std::vector<size_t>& ids) {
  IdPairs out;
  for (size_t k = 0; k + 1 < ids.size(); ++k) out.emplace_back(ids[k], ids[k + 1]);
  return out;
}

IdPairs pairs_by_path(const PoseList& poses, double delta, double tol, bool all_pairs) {
  if (!all_pairs) {
    // The first pair starts where the path first reaches delta, not at index 0 (as evo).
    std::vector<size_t> ids;
    double path = 0.0;
    for (size_t i = 0; i < poses.size(); ++i) {
      if (i > 0) path += (poses[i].translation() - poses[i - 1].translation()).norm();
      if (path >= delta) {
        ids.push_back(i);
        path = 0.0;
      }
    }
    return consecutive(ids);
  }
  std::vector<double> dist(poses.size(), 0.0);  // accumulated path length, sequential sum
  for (size_t i = 1; i < poses.size(); ++i)
    dist[i] = dist[i - 1] + (poses[i].translation() - poses[i - 1].translation()).norm();
  IdPairs out;
  for (size_t i = 0; i + 1 < poses.size(); ++i) {
    auto from_here = [&](size_t j) { return dist[j] - dist[i]; };
    const size_t j = detail::nearest_index_sorted(i + 1, poses.size(), delta, from_here);
    if (std::abs(from_here(j) - delta) <= tol) out.emplace_back(i, j);
  }
  return out;
}

double relative_angle(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return geometry::rotation_angle(a.linear().transpose() * b.linear());
}

IdPairs pairs_by_angle(const PoseList& poses, double delta, double tol, bool degrees, bool all_pairs) {
  const double unit = degrees ? kDegPerRad : 1.0;
  IdPairs out;
  if (!all_pairs) {
    // Angles between successive poses are summed from index 0; each time the sum reaches
    // delta, (start, k) is a pair and k the next start.
    double accumulated = 0.0;
    size_t start = 0;
    for (size_t k = 1; k < poses.size(); ++k) {
      accumulated += relative_angle(poses[k - 1], poses[k]) * unit;
      if (accumulated >= delta) {
        out.emplace_back(start, k);
        accumulated = 0.0;
        start = k;
      }
    }
    return out;
  }
  // Direct angle of every pair, compared in radians like evo.
  const double to_rad = degrees ? std::numbers::pi / 180.0 : 1.0;
  const double lower = delta * to_rad - tol * to_rad, upper = delta * to_rad + tol * to_rad;
  for (size_t i = 0; i + 1 < poses.size(); ++i)
    for (size_t j = i + 1; j < poses.size(); ++j) {
      const double angle = relative_angle(poses[i], poses[j]);
      if (lower <= angle && angle <= upper) out.emplace_back(i, j);
    }
  return out;
}

}  // namespace

DeltaUnit parse_delta_unit(std::string_view name) {
  if (name == "frames" || name == "f") return DeltaUnit::frames;
  if (name == "m" || name == "meters") return DeltaUnit::meters;
  if (name == "deg" || name == "d" || name == "degrees") return DeltaUnit::degrees;
  if (name == "rad" || name == "r" || name == "radians") return DeltaUnit::radians;
  throw InputError("unknown delta unit '" + std::string(name) + "' (use frames, m, deg or rad)");
}

std::string_view delta_unit_name(DeltaUnit unit) {
  switch (unit) {
    case DeltaUnit::frames: return "frames";
    case DeltaUnit::meters: return "m";
    case DeltaUnit::degrees: return "deg";
    case DeltaUnit::radians: return "rad";
  }
  return "frames";
}

IdPairs select_pairs(const PoseList& poses, const PairOptions& options) {
  const double delta = options.delta;
  if (!(delta > 0.0) || !std::isfinite(delta)) throw InputError("the RPE delta must be a positive number");
  if (!(options.delta_tol >= 0.0)) throw InputError("the RPE delta tolerance must not be negative");
  const double tol = delta * options.delta_tol;
  IdPairs pairs;
  std::string delta_text = python_repr(delta);
  switch (options.unit) {
    case DeltaUnit::frames:
      if (delta != std::floor(delta)) throw InputError("the RPE delta in frames must be an integer");
      delta_text = std::to_string(static_cast<size_t>(delta));
      pairs = pairs_by_index(poses.size(), static_cast<size_t>(delta), options.all_pairs);
      break;
    case DeltaUnit::meters: pairs = pairs_by_path(poses, delta, tol, options.all_pairs); break;
    case DeltaUnit::degrees:
      if (delta > 180.0) throw InputError("the RPE delta angle must be within [0, 180] deg");
      pairs = pairs_by_angle(poses, delta, tol, true, options.all_pairs);
      break;
    case DeltaUnit::radians:
      if (delta > std::numbers::pi) throw InputError("the RPE delta angle must be within [0, pi] rad");
      pairs = pairs_by_angle(poses, delta, tol, false, options.all_pairs);
      break;
  }
  if (pairs.empty())
    throw EvalError(EvalErrorKind::filter, "delta = " + delta_text + " (" + std::string(delta_unit_name(options.unit)) +
                                               ") produced an empty index list - try lower values or a less "
                                               "strict tolerance");
  return pairs;
}

}  // namespace pllvo::eval
