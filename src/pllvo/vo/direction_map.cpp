#include "pllvo/vo/direction_map.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "pllvo/geometry/pose.h"
#include "pllvo/geometry/vanishing.h"

namespace pllvo::vo {

namespace {
// Segments considered when looking for a new vanishing point: the longest ones, so the pair
// search stays ~1 ms a frame.
constexpr size_t kMaxCandidates = 40;
// Segments whose interpretation planes are closer than this are one edge seen twice (a
// broken detection): they count once, and a pair of them does not fix a vanishing point.
constexpr double kSameEdgeDeg = 1.0;
// Manhattan world: proposals made before any direction was known must be this close to
// perpendicular to the ones confirmed meanwhile.
constexpr double kOrthogonalToleranceDeg = 3.0;

double residual_px(const Eigen::Vector3d& v_cam, const DirectionSegment& s, double focal) {
  const auto r = geometry::vanishing_residual(v_cam, s.start, s.end);
  return r ? std::abs(*r) * focal : std::numeric_limits<double>::infinity();
}

/// Angle (degrees) between the segment and the line from its midpoint to the vanishing point.
double angle_deg(const Eigen::Vector3d& v_cam, const DirectionSegment& s, double focal) {
  const double half_px = s.length_px / 2;
  const double r = residual_px(v_cam, s, focal);
  if (!(half_px > 0) || !std::isfinite(r)) return 90.0;
  return std::asin(std::min(1.0, r / half_px)) * 180.0 / M_PI;
}

/// Inliers of v_cam among `candidates` and how many distinct edges they are.
std::pair<std::vector<size_t>, int> support(const Eigen::Vector3d& v_cam, const std::vector<size_t>& candidates,
                                            const std::vector<DirectionSegment>& segments,
                                            const std::vector<Eigen::Vector3d>& normals, double focal,
                                            double inlier_px) {
  std::vector<size_t> inliers;
  for (size_t i : candidates)
    if (residual_px(v_cam, segments[i], focal) < inlier_px) inliers.push_back(i);
  const double same = std::cos(kSameEdgeDeg * M_PI / 180.0);
  std::vector<size_t> distinct;
  for (size_t i : inliers) {
    bool seen = false;
    for (size_t j : distinct) seen = seen || std::abs(normals[i].dot(normals[j])) > same;
    if (!seen) distinct.push_back(i);
  }
  return {inliers, static_cast<int>(distinct.size())};
}

/// The direction most nearly perpendicular to all inliers' interpretation planes, by length.
Eigen::Vector3d fit_direction(const std::vector<size_t>& inliers, const std::vector<DirectionSegment>& segments,
                              const std::vector<Eigen::Vector3d>& normals) {
  Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
  for (size_t i : inliers) M += segments[i].length_px * normals[i] * normals[i].transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(M);
  return eig.eigenvectors().col(0);  // smallest eigenvalue first
}
}  // namespace

int DirectionMap::max_directions() const {
  return config_.orthogonal_only ? std::min(3, config_.max_directions) : config_.max_directions;
}

std::vector<int> DirectionMap::associate(const std::vector<DirectionSegment>& segments,
                                         const Eigen::Matrix3d& R_cam_world, double focal) const {
  std::vector<int> out(segments.size(), -1);
  std::vector<Eigen::Vector3d> v_cam;
  for (const auto& d : directions_) v_cam.push_back(R_cam_world * d);
  for (size_t i = 0; i < segments.size(); ++i) {
    if (segments[i].length_px < config_.min_length_px) continue;
    int best = -1, within = 0;
    double best_r = config_.gate_deg;
    for (size_t j = 0; j < v_cam.size(); ++j) {
      const double r = angle_deg(v_cam[j], segments[i], focal);
      if (r >= config_.gate_deg) continue;
      ++within;
      if (r < best_r) best_r = r, best = static_cast<int>(j);
    }
    if (within == 1) out[i] = best;
  }
  return out;
}

int DirectionMap::discover(const std::vector<DirectionSegment>& segments, const Eigen::Matrix3d& R_cam_world,
                           double focal) {
  const std::vector<int> known = associate(segments, R_cam_world, focal);
  std::vector<size_t> candidates;
  for (size_t i = 0; i < segments.size(); ++i)
    if (known[i] < 0 && segments[i].length_px >= config_.min_length_px) candidates.push_back(i);
  const int added = confirm_pending(segments, candidates, R_cam_world, focal, true);
  std::stable_sort(candidates.begin(), candidates.end(),
                   [&](size_t a, size_t b) { return segments[a].length_px > segments[b].length_px; });
  if (candidates.size() > kMaxCandidates) candidates.resize(kMaxCandidates);
  std::vector<Eigen::Vector3d> normals(segments.size(), Eigen::Vector3d::Zero());
  for (size_t i : candidates) normals[i] = geometry::interpretation_plane_normal(segments[i].start, segments[i].end);

  const double min_sin_pair = std::sin(kSameEdgeDeg * M_PI / 180.0);
  while (static_cast<int>(directions_.size() + pending_.size()) < max_directions() &&
         static_cast<int>(candidates.size()) >= config_.min_support) {
    // Hypotheses (camera frame): in a Manhattan world a new direction is perpendicular to the
    // known ones, so one segment fixes it beside one known direction and none beside two;
    // otherwise two segments meet at its vanishing point.
    std::vector<Eigen::Vector3d> known_cam;
    if (config_.orthogonal_only)
      for (const auto& d : directions_) known_cam.push_back(R_cam_world * d);
    std::vector<Eigen::Vector3d> hypotheses;
    if (known_cam.size() >= 2) {
      hypotheses.push_back(known_cam[0].cross(known_cam[1]));
    } else if (known_cam.size() == 1) {
      for (size_t i : candidates) hypotheses.push_back(normals[i].cross(known_cam[0]));
    } else {
      for (size_t a = 0; a < candidates.size(); ++a)
        for (size_t b = a + 1; b < candidates.size(); ++b)
          hypotheses.push_back(normals[candidates[a]].cross(normals[candidates[b]]));
    }
    int best_distinct = 0;
    Eigen::Vector3d best_v = Eigen::Vector3d::Zero();
    for (const auto& v : hypotheses) {
      if (v.norm() < min_sin_pair) continue;
      const int distinct = support(v, candidates, segments, normals, focal, config_.inlier_px).second;
      if (distinct > best_distinct) best_distinct = distinct, best_v = v.normalized();
    }
    if (best_distinct < config_.min_support) break;
    auto [inliers, distinct] = support(best_v, candidates, segments, normals, focal, config_.inlier_px);
    Eigen::Vector3d v = best_v;
    if (known_cam.empty()) {
      v = fit_direction(inliers, segments, normals);
      std::tie(inliers, distinct) = support(v, candidates, segments, normals, focal, config_.inlier_px);
      if (distinct < config_.min_support) break;
    }
    const Eigen::Vector3d d = (R_cam_world.transpose() * v).normalized();
    if (separate(d)) pending_.push_back({d, 1, 0});
    std::vector<char> used(segments.size(), 0);
    for (size_t i : inliers) used[i] = 1;
    candidates.erase(std::remove_if(candidates.begin(), candidates.end(), [&](size_t i) { return used[i]; }),
                     candidates.end());
  }
  std::vector<size_t> none;
  return added + confirm_pending({}, none, R_cam_world, focal, false);
}

bool DirectionMap::orthogonal_to_known(const Eigen::Vector3d& d) const {
  if (!config_.orthogonal_only) return true;
  const double max_cos = std::sin(kOrthogonalToleranceDeg * M_PI / 180.0);
  for (const auto& e : directions_)
    if (std::abs(e.dot(d)) > max_cos) return false;
  return true;
}

bool DirectionMap::separate(const Eigen::Vector3d& d) const {
  const double max_cos = std::cos(config_.min_separation_deg * M_PI / 180.0);
  for (const auto& e : directions_)
    if (std::abs(e.dot(d)) >= max_cos) return false;
  for (const auto& c : pending_)
    if (std::abs(c.direction.dot(d)) >= max_cos) return false;
  return true;
}

int DirectionMap::confirm_pending(const std::vector<DirectionSegment>& segments, std::vector<size_t>& candidates,
                                  const Eigen::Matrix3d& R_cam_world, double focal, bool count_frame) {
  int added = 0;
  std::vector<Pending> kept;
  for (auto c : pending_) {
    // Seen again: min_support segments (not on a known direction) point at it. The frame
    // that proposed it (age 0) counts once, in the proposal.
    if (count_frame) {
      const Eigen::Vector3d v = R_cam_world * c.direction;
      std::vector<size_t> on;
      for (size_t i : candidates)
        if (angle_deg(v, segments[i], focal) < config_.gate_deg) on.push_back(i);
      ++c.age;
      if (static_cast<int>(on.size()) >= config_.min_support) {
        ++c.seen;
        candidates.erase(std::remove_if(candidates.begin(), candidates.end(),
                                        [&](size_t i) { return std::find(on.begin(), on.end(), i) != on.end(); }),
                         candidates.end());
      }
    }
    if (c.seen >= config_.confirm_frames) {
      if (orthogonal_to_known(c.direction)) {
        directions_.push_back(c.direction);
        ++added;
      }
    } else if (c.age < config_.confirm_frames + 2) {
      kept.push_back(c);
    }
  }
  pending_ = std::move(kept);
  return added;
}

std::vector<Eigen::Vector3d> image_directions(const std::vector<DirectionSegment>& segments, double focal,
                                              DirectionConfig config) {
  config.confirm_frames = 1;
  DirectionMap map(config);
  map.discover(segments, Eigen::Matrix3d::Identity(), focal);
  std::vector<Eigen::Vector3d> out = map.directions();
  if (!config.orthogonal_only || out.size() < 2) return out;
  // Each was fitted on its own segments; the nearest orthonormal frame shares out their errors.
  Eigen::Matrix3d M;
  M.col(0) = out[0];
  M.col(1) = out[1];
  const Eigen::Vector3d third = out[0].cross(out[1]).normalized();
  M.col(2) = out.size() > 2 ? (out[2].dot(third) < 0 ? -out[2] : out[2]) : third;
  const Eigen::Matrix3d R = geometry::nearest_rotation(M);
  for (size_t k = 0; k < out.size(); ++k) out[k] = R.col(static_cast<int>(k));
  return out;
}

}  // namespace pllvo::vo
