#include "pllvo/geometry/two_view.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include "pllvo/geometry/pose.h"
#include "pllvo/geometry/triangulation.h"
#include "pllvo/geometry/two_view_refine.h"

namespace pllvo::geometry {

namespace {
using two_view_detail::DirectionPairError;
using two_view_detail::DirectionPrior;
using two_view_detail::refine_motion;
using two_view_detail::sampson_px;

constexpr double kChi2OneDof = 3.841;  // 95% bound of a 1-D squared error in sigma^2
constexpr double kChi2TwoDof = 5.991;  // 95% bound of a 2-D squared error in sigma^2
constexpr double kRadToDeg = 180.0 / M_PI;
// Below this parallax the sign of a triangulated depth is noise (ORB-SLAM's cos 0.99998).
constexpr double kCheiralityMinParallaxDeg = 0.36;
// Standard deviation that holds a translation direction in place in refine_motion.
constexpr double kFixedDirectionSigmaDeg = 0.01;
// Floor of the noise behind the direction's uncertainty (pixels): noise-free matches would
// otherwise claim any short baseline exact.
constexpr double kMinDirectionNoisePx = 0.05;
constexpr const char* kFarDirection = "translation far from the expected direction";

Eigen::Vector3d homogeneous(const Eigen::Vector2d& x) { return {x.x(), x.y(), 1.0}; }

/// Squared distance (normalised units) of x to the 2-D line l.
double line_distance2(const Eigen::Vector3d& l, const Eigen::Vector2d& x) {
  const double d = l.dot(homogeneous(x));
  return d * d / l.head<2>().squaredNorm();
}

struct Candidate {
  Candidate() = default;
  Candidate(const Eigen::Matrix3d& R_, const Eigen::Vector3d& t_) : R(R_), t(t_) {}
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  int good = 0;         ///< consistent: in front (or too little parallax to tell) and reprojecting
  int informative = 0;  ///< consistent, in front, with enough parallax for the depth sign to mean something
  double median_parallax_deg = 0;
  std::vector<Eigen::Vector3d> points;
  std::vector<uint8_t> triangulated;
};

/// Triangulates the inliers under motion (R, t) and counts the consistent ones.
void evaluate(Candidate& c, std::span<const Eigen::Vector2d> xy0, std::span<const Eigen::Vector2d> xy1,
              const std::vector<uint8_t>& inliers, double max_error, const TwoViewConfig& config) {
  const size_t n = xy0.size();
  c.points.assign(n, Eigen::Vector3d::Zero());
  c.triangulated.assign(n, 0);
  c.good = c.informative = 0;
  const Pose T[2] = {Pose::Identity(), make_pose(c.R, c.t)};
  const Eigen::Vector3d centre1 = -c.R.transpose() * c.t;
  std::vector<double> parallaxes;
  for (size_t i = 0; i < n; ++i) {
    if (!inliers[i]) continue;
    const Eigen::Vector2d obs[2] = {xy0[i], xy1[i]};
    Eigen::Vector3d X;
    if (!triangulate_linear(T, obs, X)) continue;
    const Eigen::Vector3d X1 = c.R * X + c.t;
    const double cos_parallax = X.normalized().dot((X - centre1).normalized());
    const double parallax = std::acos(std::clamp(cos_parallax, -1.0, 1.0)) * kRadToDeg;
    const bool in_front = X.z() > 0 && X1.z() > 0;
    if (!in_front && parallax >= kCheiralityMinParallaxDeg) continue;
    if (std::abs(X.z()) < 1e-12 || std::abs(X1.z()) < 1e-12) continue;
    const double e0 = (X.head<2>() / X.z() - xy0[i]).norm(), e1 = (X1.head<2>() / X1.z() - xy1[i]).norm();
    if (e0 > max_error || e1 > max_error) continue;
    ++c.good;
    if (in_front && parallax >= kCheiralityMinParallaxDeg) ++c.informative;
    parallaxes.push_back(parallax);
    if (in_front && parallax >= config.min_point_parallax_deg) {
      c.points[i] = X;
      c.triangulated[i] = 1;
    }
  }
  if (!parallaxes.empty()) {
    auto mid = parallaxes.begin() + parallaxes.size() / 2;
    std::nth_element(parallaxes.begin(), mid, parallaxes.end());
    c.median_parallax_deg = *mid;
  }
}

/// Two unit vectors orthogonal to t and to each other: the tangent plane of the sphere at t.
Eigen::Matrix<double, 3, 2> sphere_tangent(const Eigen::Vector3d& t) {
  const Eigen::Vector3d a = std::abs(t.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  Eigen::Matrix<double, 3, 2> B;
  B.col(0) = t.cross(a).normalized();
  B.col(1) = t.cross(B.col(0)).normalized();
  return B;
}

/// Direction k of n spread evenly over the half sphere z >= 0 (a Fibonacci lattice); the
/// Sampson error does not see the sign of a translation.
Eigen::Vector3d hemisphere_direction(int k, int n) {
  const double z = 1.0 - (k + 0.5) / n, r = std::sqrt(std::max(0.0, 1.0 - z * z));
  const double phi = k * M_PI * (3.0 - std::sqrt(5.0));
  return {r * std::cos(phi), r * std::sin(phi), z};
}

/// Over a short baseline the Sampson cost has more than one valley (a sideways step passes for
/// a forward one with a little more rotation) and a minimal-sample RANSAC winner may lie in the
/// wrong one; a refinement from it stays there (docs/vo.md). So the motion is
/// refined from the winner and from `config.direction_search_starts` directions spread over the
/// sphere, and the one whose errors score best (ORB-SLAM's score, all matches) is kept, its
/// sign chosen by cheirality. The refinements use the matches that fit either model (a wrong
/// winner's own inliers leave out those that tell the valleys apart). Returns the winner
/// unchanged when the search is off.
Candidate search_direction(const Candidate& winner, std::span<const Eigen::Vector2d> xy0,
                           std::span<const Eigen::Vector2d> xy1, const std::vector<uint8_t>& inliers_e,
                           const std::vector<uint8_t>& inliers_h, double focal_px, double max_error,
                           const TwoViewConfig& config) {
  const int n = config.direction_search_starts;
  if (n <= 0) return Candidate(winner.R, winner.t);
  std::vector<uint8_t> inliers(inliers_e.size());
  for (size_t i = 0; i < inliers.size(); ++i) inliers[i] = inliers_e[i] || inliers_h[i];
  std::vector<uint8_t> scratch;
  Candidate best(winner.R, winner.t);
  double best_score = -1;
  for (int k = -1; k < n; ++k) {
    Candidate c(winner.R, k < 0 ? winner.t : hemisphere_direction(k, n));
    refine_motion(c.R, c.t, xy0, xy1, inliers, focal_px, config.sigma_px);
    const double score = score_essential(hat(c.t) * c.R, xy0, xy1, focal_px, config.sigma_px, scratch);
    if (score > best_score) best_score = score, best = c;
  }
  Candidate flipped(best.R, -best.t);
  evaluate(best, xy0, xy1, inliers, max_error, config);
  evaluate(flipped, xy0, xy1, inliers, max_error, config);
  return Candidate(best.R, flipped.informative > best.informative ? flipped.t : best.t);
}

/// The directions of view 0 that `R` maps within config.vanishing_gate_deg of one of view 1
/// (each used once, the closest first), signs aligned, scaled for refine_motion.
std::vector<DirectionPairError> pair_directions(const ViewDirections& dirs, const Eigen::Matrix3d& R,
                                                const TwoViewConfig& config) {
  std::vector<DirectionPairError> out;
  const double min_cos = std::cos(config.vanishing_gate_deg * M_PI / 180.0);
  const double scale = config.sigma_px / (config.vanishing_sigma_deg * M_PI / 180.0);
  std::vector<char> used(dirs.cam1.size(), 0);
  for (const auto& a : dirs.cam0) {
    const Eigen::Vector3d Ra = R * a;
    int best = -1;
    double best_cos = min_cos;
    for (size_t j = 0; j < dirs.cam1.size(); ++j)
      if (!used[j] && std::abs(dirs.cam1[j].dot(Ra)) > best_cos) best_cos = std::abs(dirs.cam1[j].dot(Ra)), best = j;
    if (best < 0) continue;
    used[best] = 1;
    const Eigen::Vector3d& b = dirs.cam1[best];
    out.push_back({a.normalized(), (b.dot(Ra) < 0 ? -b : b).normalized(), scale});
  }
  return out;
}

/// The rotation that maps each pair's a onto its b best (Wahba's problem; one pair: the
/// smallest turn of R that does it).
Eigen::Matrix3d align_directions(const std::vector<DirectionPairError>& pairs, const Eigen::Matrix3d& R) {
  if (pairs.size() == 1) {
    const Eigen::Vector3d Ra = R * pairs[0].a;
    return Eigen::Quaterniond::FromTwoVectors(Ra, pairs[0].b).toRotationMatrix() * R;
  }
  Eigen::Matrix3d B = Eigen::Matrix3d::Zero();
  for (const auto& p : pairs) B += p.b * p.a.transpose();
  return nearest_rotation(B);
}

/// With the rotation known, every match says t is perpendicular to x1 x (R x0): the unit t
/// closest to all of them (its sign is left to cheirality).
Eigen::Vector3d translation_given_rotation(const Eigen::Matrix3d& R, std::span<const Eigen::Vector2d> xy0,
                                           std::span<const Eigen::Vector2d> xy1, const std::vector<uint8_t>& inliers) {
  Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
  for (size_t i = 0; i < xy0.size(); ++i) {
    if (!inliers[i]) continue;
    const Eigen::Vector3d n = homogeneous(xy1[i]).cross(R * homogeneous(xy0[i])).normalized();
    M += n * n.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(M);
  return eig.eigenvectors().col(0);
}

/// The winner's motion with its rotation replaced by the one the direction pairs give and the
/// translation solved again under it, its sign by cheirality.
Candidate rotation_held_motion(const Candidate& winner, const std::vector<DirectionPairError>& pairs,
                               std::span<const Eigen::Vector2d> xy0, std::span<const Eigen::Vector2d> xy1,
                               const std::vector<uint8_t>& inliers, double max_error, const TwoViewConfig& config) {
  const Eigen::Matrix3d R = align_directions(pairs, winner.R);
  const Eigen::Vector3d t = translation_given_rotation(R, xy0, xy1, inliers);
  Candidate plus(R, t), minus(R, -t);
  evaluate(plus, xy0, xy1, inliers, max_error, config);
  evaluate(minus, xy0, xy1, inliers, max_error, config);
  return Candidate(R, minus.informative > plus.informative ? -t : t);
}

std::vector<cv::Point2d> to_cv(std::span<const Eigen::Vector2d> xy) {
  std::vector<cv::Point2d> out(xy.size());
  for (size_t i = 0; i < xy.size(); ++i) out[i] = {xy[i].x(), xy[i].y()};
  return out;
}

std::vector<Candidate> essential_candidates(const Eigen::Matrix3d& E) {
  cv::Mat E_cv, R1, R2, t;
  cv::eigen2cv(E, E_cv);
  cv::decomposeEssentialMat(E_cv, R1, R2, t);
  Eigen::Matrix3d Ra, Rb;
  Eigen::Vector3d te;
  cv::cv2eigen(R1, Ra);
  cv::cv2eigen(R2, Rb);
  cv::cv2eigen(t, te);
  te.normalize();
  return {Candidate(Ra, te), Candidate(Ra, -te), Candidate(Rb, te), Candidate(Rb, -te)};
}

std::vector<Candidate> homography_candidates(const Eigen::Matrix3d& H) {
  cv::Mat H_cv;
  cv::eigen2cv(H, H_cv);
  std::vector<cv::Mat> Rs, ts, normals;
  cv::decomposeHomographyMat(H_cv, cv::Mat::eye(3, 3, CV_64F), Rs, ts, normals);
  std::vector<Candidate> out;
  for (size_t i = 0; i < Rs.size(); ++i) {
    Candidate c;
    cv::cv2eigen(Rs[i], c.R);
    cv::cv2eigen(ts[i], c.t);
    if (!(c.t.norm() > 1e-12)) continue;  // pure rotation: no baseline to triangulate with
    c.t.normalize();
    out.push_back(c);
  }
  return out;
}
}  // namespace

const char* to_string(TwoViewModel model) {
  switch (model) {
    case TwoViewModel::kNone: return "none";
    case TwoViewModel::kEssential: return "essential";
    case TwoViewModel::kHomography: return "homography";
  }
  return "?";
}

void TwoViewConfig::load(const ConfigNode& node) {
  node.get("sigma_px", sigma_px);
  node.get("ransac_threshold_px", ransac_threshold_px);
  node.get("ransac_confidence", ransac_confidence);
  node.get("ransac_max_iterations", ransac_max_iterations);
  node.get("homography_ratio", homography_ratio);
  node.get("max_reprojection_error_px", max_reprojection_error_px);
  node.get("min_point_parallax_deg", min_point_parallax_deg);
  node.get("min_median_parallax_deg", min_median_parallax_deg);
  node.get("min_triangulated", min_triangulated);
  node.get("min_good_fraction", min_good_fraction);
  node.get("max_ambiguity", max_ambiguity);
  node.get("max_direction_sigma_deg", max_direction_sigma_deg);
  node.get("direction_search_starts", direction_search_starts);
  node.get("vanishing_sigma_deg", vanishing_sigma_deg);
  node.get("vanishing_gate_deg", vanishing_gate_deg);
  node.reject_unknown_keys();
}

double score_essential(const Eigen::Matrix3d& E, std::span<const Eigen::Vector2d> xy0,
                       std::span<const Eigen::Vector2d> xy1, double focal_px, double sigma_px,
                       std::vector<uint8_t>& inliers) {
  const double to_chi2 = focal_px * focal_px / (sigma_px * sigma_px);
  inliers.assign(xy0.size(), 0);
  double score = 0;
  for (size_t i = 0; i < xy0.size(); ++i) {
    const double chi1 = line_distance2(E * homogeneous(xy0[i]), xy1[i]) * to_chi2;
    const double chi0 = line_distance2(E.transpose() * homogeneous(xy1[i]), xy0[i]) * to_chi2;
    // Scored against the 2-DoF bound so that E and H scores are comparable (ORB-SLAM).
    if (chi1 <= kChi2OneDof) score += kChi2TwoDof - chi1;
    if (chi0 <= kChi2OneDof) score += kChi2TwoDof - chi0;
    inliers[i] = chi0 <= kChi2OneDof && chi1 <= kChi2OneDof;
  }
  return score;
}

double score_homography(const Eigen::Matrix3d& H_1_0, std::span<const Eigen::Vector2d> xy0,
                        std::span<const Eigen::Vector2d> xy1, double focal_px, double sigma_px,
                        std::vector<uint8_t>& inliers) {
  const double to_chi2 = focal_px * focal_px / (sigma_px * sigma_px);
  const Eigen::Matrix3d H_0_1 = H_1_0.inverse();
  inliers.assign(xy0.size(), 0);
  double score = 0;
  for (size_t i = 0; i < xy0.size(); ++i) {
    const Eigen::Vector3d p1 = H_1_0 * homogeneous(xy0[i]), p0 = H_0_1 * homogeneous(xy1[i]);
    const double chi1 = (p1.head<2>() / p1.z() - xy1[i]).squaredNorm() * to_chi2;
    const double chi0 = (p0.head<2>() / p0.z() - xy0[i]).squaredNorm() * to_chi2;
    const bool ok1 = std::isfinite(chi1) && chi1 <= kChi2TwoDof, ok0 = std::isfinite(chi0) && chi0 <= kChi2TwoDof;
    if (ok1) score += kChi2TwoDof - chi1;
    if (ok0) score += kChi2TwoDof - chi0;
    inliers[i] = ok0 && ok1;
  }
  return score;
}

TwoViewResult initialise_two_view(std::span<const Eigen::Vector2d> xy0,
                                  std::span<const Eigen::Vector2d> xy1, double focal_px,
                                  const TwoViewConfig& config, const ViewDirections* directions) {
  TwoViewResult out;
  const size_t n = xy0.size();
  out.inliers.assign(n, 0);
  out.points_cam0.assign(n, Eigen::Vector3d::Zero());
  out.triangulated.assign(n, 0);
  if (n != xy1.size() || n < 8) {
    out.failure = "too few matches";
    return out;
  }

  const auto p0 = to_cv(xy0), p1 = to_cv(xy1);
  const double threshold = config.ransac_threshold_px / focal_px;
  Eigen::Matrix3d E = Eigen::Matrix3d::Zero(), H = Eigen::Matrix3d::Zero();
  std::vector<uint8_t> inliers_e(n, 0), inliers_h(n, 0);
  try {
    const cv::Mat E_cv = cv::findEssentialMat(p0, p1, cv::Mat::eye(3, 3, CV_64F), cv::RANSAC,
                                              config.ransac_confidence, threshold,
                                              config.ransac_max_iterations);
    if (E_cv.rows == 3 && E_cv.cols == 3) {
      cv::cv2eigen(E_cv, E);
      out.score_essential = score_essential(E, xy0, xy1, focal_px, config.sigma_px, inliers_e);
    }
    const cv::Mat H_cv = cv::findHomography(p0, p1, cv::RANSAC, threshold, cv::noArray(),
                                            config.ransac_max_iterations, config.ransac_confidence);
    if (H_cv.rows == 3 && H_cv.cols == 3) {
      cv::cv2eigen(H_cv, H);
      out.score_homography = score_homography(H, xy0, xy1, focal_px, config.sigma_px, inliers_h);
    }
  } catch (const cv::Exception&) {
    // Degenerate input (e.g. all matches identical): whatever was fitted before still counts.
  }
  const double total = out.score_essential + out.score_homography;
  if (!(total > 0)) {
    out.failure = "no model fits the matches";
    return out;
  }
  const bool use_h = out.score_homography / total > config.homography_ratio;
  out.model = use_h ? TwoViewModel::kHomography : TwoViewModel::kEssential;
  out.inliers = use_h ? inliers_h : inliers_e;
  const int num_inliers = static_cast<int>(std::count(out.inliers.begin(), out.inliers.end(), 1));

  std::vector<Candidate> candidates = use_h ? homography_candidates(H) : essential_candidates(E);
  const double max_error = config.max_reprojection_error_px / focal_px;
  for (auto& c : candidates) evaluate(c, xy0, xy1, out.inliers, max_error, config);
  // Points too far to show their depth sign fit every candidate; only the others tell
  // candidates apart.
  std::sort(candidates.begin(), candidates.end(),
            [](const Candidate& a, const Candidate& b) { return a.informative > b.informative; });
  if (candidates.empty() || candidates[0].informative == 0) {
    out.failure = "no decomposition explains the matches";
    return out;
  }
  const Candidate& best = candidates[0];
  out.median_parallax_deg = best.median_parallax_deg;
  const int num_triangulated = static_cast<int>(std::count(best.triangulated.begin(), best.triangulated.end(), 1));
  out.num_triangulated = num_triangulated;
  if (best.good < config.min_good_fraction * num_inliers) {
    out.failure = "too few inliers in front of both cameras";
  } else if (candidates.size() > 1 && candidates[1].informative > config.max_ambiguity * best.informative) {
    out.failure = "ambiguous decomposition";
  } else if (best.median_parallax_deg < config.min_median_parallax_deg) {
    out.failure = "parallax too low";
  } else if (num_triangulated < config.min_triangulated) {
    out.failure = "too few triangulated points";
  }
  if (!out.failure.empty()) return out;

  // Refine the winner, re-select the inliers with the refined motion (the RANSAC model's
  // inlier set is biased by its error), refine again, and triangulate with the result.
  Candidate refined = search_direction(best, xy0, xy1, inliers_e, inliers_h, focal_px, max_error, config);
  std::vector<uint8_t> refined_inliers = out.inliers;
  std::vector<DirectionPairError> pairs;
  if (directions && config.vanishing_sigma_deg > 0) pairs = pair_directions(*directions, best.R, config);
  out.vanishing_pairs = static_cast<int>(pairs.size());
  if (!pairs.empty()) refined = rotation_held_motion(best, pairs, xy0, xy1, out.inliers, max_error, config);
  for (int pass = 0; pass < 2; ++pass) {
    refine_motion(refined.R, refined.t, xy0, xy1, refined_inliers, focal_px, config.sigma_px, nullptr,
                  pairs.empty() ? nullptr : &pairs);
    score_essential(hat(refined.t) * refined.R, xy0, xy1, focal_px, config.sigma_px, refined_inliers);
  }
  evaluate(refined, xy0, xy1, refined_inliers, max_error, config);
  // Without the search, the refinement may slide a weakly determined translation (small
  // parallax, homography start) to a motion that explains the matches but triangulates
  // nothing: it is kept only when it still passes the same checks as the RANSAC winner. With
  // the search, or with the rotation held by directions, the refined motion is the estimate
  // and must pass them itself.
  const int refined_triangulated =
      static_cast<int>(std::count(refined.triangulated.begin(), refined.triangulated.end(), 1));
  const bool refined_passes = refined.median_parallax_deg >= config.min_median_parallax_deg &&
                              refined_triangulated >= config.min_triangulated;
  const bool refined_is_estimate = config.direction_search_starts > 0 || !pairs.empty();
  const bool use_refined =
      refined_is_estimate || (refined.good >= best.good * config.min_good_fraction && refined_passes);
  const Candidate& final_motion = use_refined ? refined : best;
  if (use_refined) out.inliers = refined_inliers;
  if (refined_is_estimate && !refined_passes) {
    // The searched (or rotation-held) motion explains the matches best; the winner's larger
    // parallax belongs to a wrong motion (docs/vo.md), so the start waits for a
    // longer baseline.
    out.median_parallax_deg = refined.median_parallax_deg;
    out.num_triangulated = refined_triangulated;
    out.failure = refined.median_parallax_deg < config.min_median_parallax_deg ? "parallax too low"
                                                                               : "too few triangulated points";
    return out;
  }
  out.T_cam1_cam0 = make_pose(final_motion.R, final_motion.t);
  out.direction = translation_direction_uncertainty(out.T_cam1_cam0, xy0, xy1, out.inliers, focal_px);
  out.median_parallax_deg = final_motion.median_parallax_deg;
  if (config.max_direction_sigma_deg > 0 && !(out.direction.sigma_deg <= config.max_direction_sigma_deg)) {
    out.failure = "translation direction uncertain";
    return out;
  }
  out.ok = true;
  out.points_cam0 = final_motion.points;
  out.triangulated = final_motion.triangulated;
  out.num_triangulated =
      static_cast<int>(std::count(final_motion.triangulated.begin(), final_motion.triangulated.end(), 1));
  return out;
}

RelativeMotion estimate_relative_motion(std::span<const Eigen::Vector2d> xy0,
                                        std::span<const Eigen::Vector2d> xy1, double focal_px,
                                        const Pose& expected_T_cam1_cam0, const RelativeMotionLimits& limits,
                                        const TwoViewConfig& config) {
  RelativeMotion out;
  const size_t n = xy0.size();
  out.inliers.assign(n, 0);
  if (n != xy1.size() || static_cast<int>(n) < std::max(limits.min_inliers, 8)) {
    out.failure = "too few matches";
    return out;
  }
  Eigen::Matrix3d E = Eigen::Matrix3d::Zero();
  try {
    const cv::Mat E_cv = cv::findEssentialMat(to_cv(xy0), to_cv(xy1), cv::Mat::eye(3, 3, CV_64F), cv::RANSAC,
                                              config.ransac_confidence, config.ransac_threshold_px / focal_px,
                                              config.ransac_max_iterations);
    if (E_cv.rows != 3 || E_cv.cols != 3) {
      out.failure = "no essential matrix";
      return out;
    }
    cv::cv2eigen(E_cv, E);
  } catch (const cv::Exception&) {
    out.failure = "no essential matrix";
    return out;
  }
  score_essential(E, xy0, xy1, focal_px, config.sigma_px, out.inliers);
  std::vector<Candidate> candidates = essential_candidates(E);
  const double max_error = config.max_reprojection_error_px / focal_px;
  for (auto& c : candidates) evaluate(c, xy0, xy1, out.inliers, max_error, config);
  const Candidate& best = *std::max_element(candidates.begin(), candidates.end(),
      [](const Candidate& a, const Candidate& b) { return a.informative < b.informative; });
  const Eigen::Vector3d t_expected = expected_T_cam1_cam0.translation();
  // A refinement from the winner, its translation pulled towards the expected direction with
  // standard deviation sigma_deg (0: free), judged against the limits.
  auto fit = [&](const Eigen::Vector3d& t_start, double sigma_deg) {
    Eigen::Matrix3d R = best.R;
    Eigen::Vector3d t = t_start;
    if (t_expected.norm() > 0 && sigma_deg > 0) {
      const DirectionPrior prior{t_expected.normalized(), config.sigma_px / (sigma_deg / kRadToDeg)};
      refine_motion(R, t, xy0, xy1, out.inliers, focal_px, config.sigma_px, &prior);
    } else {
      refine_motion(R, t, xy0, xy1, out.inliers, focal_px, config.sigma_px);
    }
    score_essential(hat(t) * R, xy0, xy1, focal_px, config.sigma_px, out.inliers);
    out.num_inliers = static_cast<int>(std::count(out.inliers.begin(), out.inliers.end(), 1));
    out.T_cam1_cam0 = make_pose(R, t);
    out.rotation_from_expected_deg = rotation_angle(R * expected_T_cam1_cam0.linear().transpose()) * kRadToDeg;
    out.translation_from_expected_deg =
        t_expected.norm() > 0 ? std::acos(std::clamp(t.dot(t_expected.normalized()), -1.0, 1.0)) * kRadToDeg : 0.0;
    out.failure.clear();
    if (out.num_inliers < limits.min_inliers) {
      out.failure = "too few inliers";
    } else if (out.rotation_from_expected_deg > limits.max_rotation_change_deg) {
      out.failure = "rotation far from the expected one";
    } else if (out.translation_from_expected_deg > limits.max_translation_change_deg) {
      out.failure = kFarDirection;
    }
  };
  fit(best.t, limits.translation_prior_sigma_deg);
  if (out.failure == kFarDirection && limits.keep_expected_translation) {
    // The matches do not tell the direction (too little parallax, or too few of them): the
    // rotation alone is measured, the translation kept as expected.
    const std::vector<uint8_t> essential_inliers = out.inliers;
    fit(t_expected.normalized(), kFixedDirectionSigmaDeg);
    if (!out.failure.empty()) out.inliers = essential_inliers;
    out.translation_kept = true;
  }
  out.ok = out.failure.empty();
  return out;
}

DirectionUncertainty translation_direction_uncertainty(const Pose& T_cam1_cam0, std::span<const Eigen::Vector2d> xy0,
                                                       std::span<const Eigen::Vector2d> xy1,
                                                       const std::vector<uint8_t>& inliers, double focal_px) {
  DirectionUncertainty out;
  const Eigen::Matrix3d R = T_cam1_cam0.linear();
  const Eigen::Vector3d t = T_cam1_cam0.translation().normalized();
  const Eigen::Matrix<double, 3, 2> B = sphere_tangent(t);
  // Motion perturbation d: rotation Exp(d[0..2]) * R, direction normalize(t + B d[3..4]).
  auto residual = [&](size_t i, const Eigen::Matrix<double, 5, 1>& d) {
    return sampson_px(so3_exp(d.head<3>()) * R, (t + B * d.tail<2>()).normalized(), xy0[i], xy1[i], focal_px);
  };
  constexpr double kStep = 1e-6;
  Eigen::Matrix<double, 5, 5> information = Eigen::Matrix<double, 5, 5>::Zero();
  double sum2 = 0;
  for (size_t i = 0; i < xy0.size() && i < xy1.size() && i < inliers.size(); ++i) {
    if (!inliers[i]) continue;
    const double r = residual(i, Eigen::Matrix<double, 5, 1>::Zero());
    Eigen::Matrix<double, 1, 5> J;
    for (int k = 0; k < 5; ++k) {
      Eigen::Matrix<double, 5, 1> d = Eigen::Matrix<double, 5, 1>::Zero();
      d[k] = kStep;
      J[k] = (residual(i, d) - residual(i, -d)) / (2 * kStep);
    }
    information += J.transpose() * J;
    sum2 += r * r;
    ++out.num_matches;
  }
  if (out.num_matches < 6) return out;
  // The matches' own scatter is the noise: low light's noisier tracks fix the direction less.
  out.residual_rms_px = std::sqrt(sum2 / out.num_matches);
  const double noise_px = std::max(out.residual_rms_px, kMinDirectionNoisePx);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 5, 5>> eig(information);
  if (eig.info() != Eigen::Success || !(eig.eigenvalues()[0] > 1e-12 * eig.eigenvalues()[4])) return out;
  const Eigen::Matrix<double, 5, 5> covariance =
      noise_px * noise_px * eig.eigenvectors() * eig.eigenvalues().cwiseInverse().asDiagonal() *
      eig.eigenvectors().transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> dir(covariance.bottomRightCorner<2, 2>());
  out.sigma_deg = std::sqrt(std::max(dir.eigenvalues()[1], 0.0)) * kRadToDeg;
  return out;
}

}  // namespace pllvo::geometry
