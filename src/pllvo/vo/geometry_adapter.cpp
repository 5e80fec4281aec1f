#include "pllvo/vo/geometry_adapter.h"

#include <algorithm>
#include <cmath>
#include <chrono>
#include <map>
#include <set>

#include "pllvo/backend/pose_refiner.h"
#include "pllvo/backend/sliding_window_ba.h"
#include "pllvo/common/statistics.h"
#include "pllvo/geometry/pnp.h"
#include "pllvo/geometry/reprojection.h"
#include "pllvo/geometry/stereo_triangulation.h"
#include "pllvo/geometry/triangulation.h"
#include "pllvo/geometry/two_view.h"

namespace pllvo::vo {

bool Pinhole::project(const Eigen::Vector3d& p, Eigen::Vector2d& px) const {
  if (!(p.z() > 1e-6)) return false;
  px = {fx * p.x() / p.z() + cx, fy * p.y() / p.z() + cy};
  return true;
}

bool Pinhole::inside(const Eigen::Vector2d& px, double border) const {
  return px.x() >= border && px.y() >= border && px.x() <= width - 1 - border && px.y() <= height - 1 - border;
}

namespace {

std::vector<Eigen::Vector2d> normalised(const Pinhole& cam, const std::vector<Eigen::Vector2d>& px) {
  std::vector<Eigen::Vector2d> xy;
  xy.reserve(px.size());
  for (const auto& p : px) xy.push_back(cam.normalised(p));
  return xy;
}

Eigen::Vector3d observed_line(const Pinhole& cam, const Segment2d& s) {
  return geometry::line_through(cam.normalised(s.a), cam.normalised(s.b));
}

}  // namespace

PoseEstimate estimate_pose_pnp(const Pinhole& cam, const std::vector<Eigen::Vector3d>& points_world,
                               const std::vector<Eigen::Vector2d>& pixels, const geometry::PnpConfig& config) {
  PoseEstimate est;
  const auto xy = normalised(cam, pixels);
  const auto pnp = geometry::solve_pnp_ransac(points_world, xy, cam.focal(), config);
  if (!pnp.ok) return est;
  est.ok = true;
  est.from_pnp = true;
  est.T_world_cam = pnp.T_world_cam;
  est.point_inliers.assign(pnp.inliers.begin(), pnp.inliers.end());
  est.num_point_inliers = pnp.num_inliers;
  return est;
}

PoseEstimate estimate_pose(const Pinhole& cam, const std::vector<Eigen::Vector3d>& points_world,
                           const std::vector<Eigen::Vector2d>& pixels, const std::vector<LineMeasurement>& lines,
                           const std::optional<geometry::Pose>& predicted_T_world_cam,
                           const geometry::GeometryConfig& geometry, const backend::BackendConfig& backend,
                           const PoseExtras& extras) {
  PoseEstimate est;
  const auto xy = normalised(cam, pixels);
  geometry::PnpResult pnp;
  if (static_cast<int>(points_world.size()) >= geometry.pnp.min_inliers)
    pnp = geometry::solve_pnp_ransac(points_world, xy, cam.focal(), geometry.pnp);
  if (!pnp.ok && !predicted_T_world_cam) return est;

  // Refinement on the PnP inliers (the RANSAC outliers are gross and would only bias the
  // first round), or on everything when starting from the prediction.
  backend::PoseRefinementProblem problem;
  problem.T_world_cam = pnp.ok ? pnp.T_world_cam : *predicted_T_world_cam;
  problem.focal_px = cam.focal();
  problem.predicted_T_world_cam = predicted_T_world_cam;
  std::vector<int> used;
  for (size_t i = 0; i < points_world.size(); ++i) {
    if (pnp.ok && !pnp.inliers[i]) continue;
    problem.points.push_back({points_world[i], xy[i]});
    used.push_back(static_cast<int>(i));
  }
  for (const auto& l : lines) problem.lines.push_back({l.start_world, l.end_world, observed_line(cam, l.observed), 0});
  if (extras.direction_weight > 0)
    problem.directions = extras.directions, problem.direction_weight = extras.direction_weight;
  const auto refined = backend::PoseRefiner(backend.pose_refiner).refine(problem);
  if (!refined.ok) return est;
  est.ok = true;
  est.from_pnp = pnp.ok;
  est.T_world_cam = refined.T_world_cam;
  est.point_inliers.assign(points_world.size(), 0);
  for (size_t k = 0; k < used.size(); ++k) est.point_inliers[used[k]] = refined.point_inliers[k];
  est.line_inliers.assign(refined.line_inliers.begin(), refined.line_inliers.end());
  est.num_point_inliers = refined.num_point_inliers;
  est.num_line_inliers = refined.num_line_inliers;
  return est;
}

TwoViewInit initialize_two_view(const Pinhole& cam, const std::vector<Eigen::Vector2d>& px0,
                                const std::vector<Eigen::Vector2d>& px1, const geometry::TwoViewConfig& config,
                                const geometry::ViewDirections* directions) {
  TwoViewInit init;
  const auto r =
      geometry::initialise_two_view(normalised(cam, px0), normalised(cam, px1), cam.focal(), config, directions);
  init.model = geometry::to_string(r.model);
  init.failure = r.failure;
  init.median_parallax_deg = r.median_parallax_deg;
  init.num_inliers = static_cast<int>(std::count(r.inliers.begin(), r.inliers.end(), 1));
  init.num_triangulated = r.num_triangulated;
  init.direction_sigma_deg = r.direction.sigma_deg;
  init.residual_rms_px = r.direction.residual_rms_px;
  init.vanishing_pairs = r.vanishing_pairs;
  if (!r.ok) return init;
  init.ok = true;
  init.T_cam1_cam0 = r.T_cam1_cam0;
  init.points_cam0.resize(px0.size());
  for (size_t i = 0; i < px0.size(); ++i)
    if (r.triangulated[i]) init.points_cam0[i] = r.points_cam0[i];
  return init;
}

std::optional<Eigen::Vector3d> triangulate_point(const Pinhole& cam, const std::vector<geometry::Pose>& T_world_cam,
                                                 const std::vector<Eigen::Vector2d>& pixels,
                                                 const geometry::PointTriangulationConfig& config) {
  const auto t = geometry::triangulate_point(T_world_cam, normalised(cam, pixels), cam.focal(), config);
  if (!t.ok()) return std::nullopt;
  return t.p_world;
}

std::vector<double> reprojection_errors_px(const Pinhole& cam, const std::vector<Eigen::Vector3d>& points_world,
                                           const std::vector<Eigen::Vector2d>& pixels,
                                           const geometry::Pose& T_world_cam) {
  const geometry::Pose T_cam_world = T_world_cam.inverse();
  std::vector<double> errors;
  for (size_t i = 0; i < points_world.size() && i < pixels.size(); ++i) {
    Eigen::Vector2d uv;
    errors.push_back(cam.project(T_cam_world * points_world[i], uv) ? (uv - pixels[i]).norm() : 1e9);
  }
  return errors;
}

double median_reprojection_px(const Pinhole& cam, const std::vector<Eigen::Vector3d>& points_world,
                              const std::vector<Eigen::Vector2d>& pixels, const geometry::Pose& T_world_cam) {
  return median(reprojection_errors_px(cam, points_world, pixels, T_world_cam));
}

std::optional<geometry::Pose> follow_keyframe_adjustment(const Pinhole& cam,
                                                         const std::vector<Eigen::Vector3d>& points_world,
                                                         const std::vector<Eigen::Vector2d>& pixels,
                                                         const geometry::Pose& T_world_current,
                                                         const geometry::Pose& T_world_added,
                                                         const geometry::Pose& T_world_adjusted, double gate_px) {
  const double now = median_reprojection_px(cam, points_world, pixels, T_world_current);
  if (points_world.empty() || now <= gate_px) return std::nullopt;
  const geometry::Pose moved = T_world_adjusted * T_world_added.inverse() * T_world_current;
  if (median_reprojection_px(cam, points_world, pixels, moved) >= now) return std::nullopt;
  return moved;
}

std::optional<geometry::Pose> pose_of_merged_tracks(const Pinhole& cam, const std::vector<Eigen::Vector3d>& points_world,
                                                    const std::vector<Eigen::Vector2d>& pixels,
                                                    const geometry::Pose& T_world_current, double gate_px,
                                                    const geometry::PnpConfig& config) {
  auto within_gate = [&](const geometry::Pose& T) {
    const std::vector<double> e = reprojection_errors_px(cam, points_world, pixels, T);
    return static_cast<size_t>(std::count_if(e.begin(), e.end(), [gate_px](double x) { return x <= gate_px; }));
  };
  const size_t now = within_gate(T_world_current);
  if (2 * now >= points_world.size()) return std::nullopt;
  const PoseEstimate e = estimate_pose_pnp(cam, points_world, pixels, config);
  if (!e.ok) return std::nullopt;
  const size_t at_pnp = within_gate(e.T_world_cam);
  if (at_pnp == 0 || at_pnp < 2 * now) return std::nullopt;
  return e.T_world_cam;
}

geometry::Pose T_left_right(double baseline) {
  geometry::Pose T = geometry::Pose::Identity();
  T.translation() = Eigen::Vector3d(baseline, 0, 0);
  return T;
}

std::optional<Eigen::Vector3d> triangulate_stereo(const Pinhole& cam, double baseline, const Eigen::Vector2d& left,
                                                  const Eigen::Vector2d& right,
                                                  const geometry::StereoTriangulationConfig& config) {
  camera::PinholeIntrinsics k;
  k.fx = cam.fx, k.fy = cam.fy, k.cx = cam.cx, k.cy = cam.cy;
  const auto s = geometry::triangulate_stereo(left, right, k, baseline, config);
  if (!s.ok()) return std::nullopt;
  return s.p_left;
}

WindowBaResult bundle_adjust_window(Map& map, const Pinhole& cam, double baseline, const std::vector<Id>& window,
                                    int max_anchors, const backend::BundleAdjustmentConfig& config,
                                    double direction_weight, double stereo_offset_px) {
  WindowBaResult result;
  result.stereo_offset_px = stereo_offset_px;
  if (window.size() < 2) return result;
  backend::BaProblem problem;
  problem.focal_px = cam.focal();
  if (baseline > 0) problem.T_cam_cam0 = {geometry::Pose::Identity(), T_left_right(baseline).inverse()};
  problem.stereo_offset_px = stereo_offset_px;
  std::vector<Id> keyframes, points, lines;
  std::vector<Observation> point_refs, line_refs;  // (keyframe, feature/line index) per observation

  map.read([&](const MapData& m) {
    const std::set<Id> in_window(window.begin(), window.end());
    std::set<Id> point_set, line_set;
    for (Id k : window) {
      const Keyframe& kf = m.keyframes.at(k);
      for (Id p : kf.point_ids)
        if (p != kNoId) point_set.insert(p);
      for (Id l : kf.line_ids)
        if (l != kNoId) line_set.insert(l);
    }
    // Anchors: the newest older keyframes of the segment that share points with the window.
    std::map<Id, int> shared;
    const int segment = m.keyframes.at(window.front()).segment;
    for (Id p : point_set)
      for (const auto& o : m.points.at(p).observations)
        if (!in_window.count(o.keyframe) && o.keyframe < window.front() &&
            m.keyframes.at(o.keyframe).segment == segment)
          ++shared[o.keyframe];
    std::vector<Id> anchors;
    for (auto it = shared.rbegin(); it != shared.rend() && static_cast<int>(anchors.size()) < max_anchors; ++it)
      anchors.push_back(it->first);
    std::sort(anchors.begin(), anchors.end());

    std::map<Id, int> kf_index, point_index, line_index;
    for (Id k : anchors) {
      kf_index[k] = static_cast<int>(keyframes.size());
      keyframes.push_back(k);
      problem.keyframes.push_back({m.keyframes.at(k).T_world_cam, true});
    }
    for (Id k : window) {
      kf_index[k] = static_cast<int>(keyframes.size());
      keyframes.push_back(k);
      problem.keyframes.push_back({m.keyframes.at(k).T_world_cam, false});
    }
    for (Id p : point_set) {
      point_index[p] = static_cast<int>(points.size());
      points.push_back(p);
      problem.points.push_back({m.points.at(p).position, false});
    }
    for (Id l : line_set) {
      line_index[l] = static_cast<int>(lines.size());
      lines.push_back(l);
      problem.lines.push_back({{m.lines.at(l).p, m.lines.at(l).q}, false});
    }
    for (Id k : keyframes) {
      const Keyframe& kf = m.keyframes.at(k);
      for (size_t i = 0; i < kf.point_ids.size(); ++i) {
        auto it = point_index.find(kf.point_ids[i]);
        if (it == point_index.end()) continue;
        const Eigen::Vector2d px(kf.features.points[i].x, kf.features.points[i].y);
        problem.point_observations.push_back({kf_index[k], it->second, 0, cam.normalised(px)});
        point_refs.push_back({k, static_cast<int>(i)});
        if (baseline > 0 && i < kf.right_points.size() && !std::isnan(kf.right_points[i].x)) {
          const Eigen::Vector2d rpx(kf.right_points[i].x, kf.right_points[i].y);
          problem.point_observations.push_back({kf_index[k], it->second, 1, cam.normalised(rpx)});
          point_refs.push_back({k, static_cast<int>(i)});
        }
      }
      for (size_t i = 0; i < kf.line_ids.size(); ++i) {
        auto it = line_index.find(kf.line_ids[i]);
        if (it == line_index.end()) continue;
        problem.line_observations.push_back({kf_index[k], it->second, 0, observed_line(cam, kf.lines[i])});
        line_refs.push_back({k, static_cast<int>(i)});
      }
      if (direction_weight > 0)
        for (const auto& d : kf.directions)
          problem.direction_observations.push_back({kf_index[k], d.direction_world, d.start, d.end});
    }
    problem.direction_weight = direction_weight;
  });

  const auto summary = backend::SlidingWindowBA(config).optimize(problem);
  result.ran = true;
  result.final_rms_px = summary.final_rms_px;
  result.solve_ms = summary.solve_time_s * 1e3;
  if (!summary.ok) return result;
  result.stereo_offset_px = problem.stereo_offset_px;

  map.write([&](MapData& m) {
    for (size_t i = 0; i < keyframes.size(); ++i)
      if (!problem.keyframes[i].fixed) m.keyframes.at(keyframes[i]).T_world_cam = problem.keyframes[i].T_world_cam;
    for (size_t i = 0; i < points.size(); ++i) {
      auto it = m.points.find(points[i]);
      if (it != m.points.end()) it->second.position = problem.points[i].p_world;
    }
    for (size_t i = 0; i < lines.size(); ++i) {
      auto it = m.lines.find(lines[i]);
      if (it == m.lines.end()) continue;
      it->second.p = problem.lines[i].segment_world.start;
      it->second.q = problem.lines[i].segment_world.end;
    }
    for (size_t j = 0; j < point_refs.size(); ++j) {
      if (!summary.point_outliers[j]) continue;
      const Observation& o = point_refs[j];
      const Id p = points[problem.point_observations[j].point];
      auto& right = m.keyframes.at(o.keyframe).right_points;
      if (o.index < static_cast<int>(right.size())) right[o.index] = cv::Point2f(NAN, NAN);
      if (problem.point_observations[j].camera == 0) m.unobserve_point(p, o.keyframe, o.index);
      ++result.point_outliers;
    }
    for (size_t j = 0; j < line_refs.size(); ++j) {
      if (!summary.line_outliers[j]) continue;
      const Observation& o = line_refs[j];
      m.unobserve_line(lines[problem.line_observations[j].line], o.keyframe, o.index);
      ++result.line_outliers;
    }
  });
  return result;
}

}  // namespace pllvo::vo
