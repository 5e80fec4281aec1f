#pragma once
// Synthetic scenes for the geometry and back-end tests: random 3-D points and line segments
// in front of a few cameras, with exact and noisy normalised observations.
#include <random>
#include <vector>

#include <Eigen/Geometry>

#include "pllvo/geometry/line3d.h"
#include "pllvo/geometry/pose.h"
#include "pllvo/geometry/reprojection.h"

namespace pllvo::test {

using geometry::LineSegment3d;
using geometry::Pose;

/// A 752x480 pinhole camera with f = 450 px (EuRoC-like), in normalised units.
constexpr double kFocal = 450.0;
constexpr double kHalfWidth = 376.0 / kFocal, kHalfHeight = 240.0 / kFocal;

inline Pose random_rotation_pose(std::mt19937& rng, const Eigen::Vector3d& centre, double max_angle_deg) {
  std::normal_distribution<double> n(0, 1);
  const Eigen::Vector3d axis = Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
  const double angle = std::uniform_real_distribution<double>(-1, 1)(rng) * max_angle_deg * M_PI / 180.0;
  return geometry::make_pose(Eigen::AngleAxisd(angle, axis).toRotationMatrix(), centre);
}

/// Normalised image coordinates of p_world in camera T_world_cam; false when behind it.
inline bool observe(const Pose& T_world_cam, const Eigen::Vector3d& p_world, Eigen::Vector2d& xy) {
  return geometry::project_normalised(T_world_cam.inverse() * p_world, xy);
}

inline bool in_view(const Pose& T_world_cam, const Eigen::Vector3d& p_world) {
  Eigen::Vector2d xy;
  return observe(T_world_cam, p_world, xy) && std::abs(xy.x()) < kHalfWidth && std::abs(xy.y()) < kHalfHeight &&
         (T_world_cam.inverse() * p_world).z() > 0.5;
}

struct SyntheticScene {
  std::vector<Pose> T_world_cam;
  std::vector<Eigen::Vector3d> points;
  std::vector<LineSegment3d> lines;
};

/// `num_cams` cameras on a sideways path (spacing `baseline`, small random rotations) looking
/// along +z at a box of points and lines with depths 4..10; every landmark is seen by every
/// camera.
inline SyntheticScene make_scene(int num_cams, int num_points, int num_lines, unsigned seed,
                                 double baseline = 0.3) {
  std::mt19937 rng(seed);
  SyntheticScene s;
  for (int i = 0; i < num_cams; ++i) {
    const Eigen::Vector3d c(baseline * (i - 0.5 * (num_cams - 1)), 0.1 * std::sin(i), 0.05 * i);
    s.T_world_cam.push_back(random_rotation_pose(rng, c, 3.0));
  }
  std::uniform_real_distribution<double> ux(-2.5, 2.5), uy(-1.5, 1.5), uz(4.0, 10.0);
  auto seen_by_all = [&](const Eigen::Vector3d& p) {
    for (const auto& T : s.T_world_cam)
      if (!in_view(T, p)) return false;
    return true;
  };
  while (static_cast<int>(s.points.size()) < num_points) {
    const Eigen::Vector3d p(ux(rng), uy(rng), uz(rng));
    if (seen_by_all(p)) s.points.push_back(p);
  }
  std::normal_distribution<double> n(0, 1);
  std::uniform_real_distribution<double> len(1.0, 2.5);
  while (static_cast<int>(s.lines.size()) < num_lines) {
    const Eigen::Vector3d a(ux(rng), uy(rng), uz(rng));
    const Eigen::Vector3d b = a + len(rng) * Eigen::Vector3d(n(rng), n(rng), 0.5 * n(rng)).normalized();
    if (seen_by_all(a) && seen_by_all(b)) s.lines.push_back({a, b});
  }
  return s;
}

/// Adds zero-mean Gaussian noise of `sigma_px` pixels to a normalised point.
inline Eigen::Vector2d add_noise(const Eigen::Vector2d& xy, double sigma_px, std::mt19937& rng) {
  std::normal_distribution<double> n(0, sigma_px / kFocal);
  return xy + Eigen::Vector2d(n(rng), n(rng));
}

/// Observed 2-D line of segment `s` in camera T_world_cam, from endpoints with pixel noise;
/// the observed endpoints (normalised) are returned too.
inline Eigen::Vector3d observe_line(const Pose& T_world_cam, const LineSegment3d& s, double sigma_px,
                                    std::mt19937& rng, Eigen::Vector2d* start = nullptr,
                                    Eigen::Vector2d* end = nullptr) {
  Eigen::Vector2d a, b;
  observe(T_world_cam, s.start, a);
  observe(T_world_cam, s.end, b);
  if (sigma_px > 0) a = add_noise(a, sigma_px, rng), b = add_noise(b, sigma_px, rng);
  if (start) *start = a;
  if (end) *end = b;
  return geometry::line_through(a, b);
}

/// Translation (norm) and rotation (degrees) difference of two poses.
inline double translation_error(const Pose& a, const Pose& b) { return (a.translation() - b.translation()).norm(); }
inline double rotation_error_deg(const Pose& a, const Pose& b) {
  return geometry::rotation_angle(a.linear().transpose() * b.linear()) * 180.0 / M_PI;
}

/// Distance from point x to the infinite line through segment s.
inline double distance_to_line(const Eigen::Vector3d& x, const LineSegment3d& s) {
  return geometry::PluckerLine::through(s).distance(x);
}

/// A segment seen by a camera (normalised endpoints) and the world direction it runs along.
struct SegmentAlong {
  Eigen::Vector2d start, end;
  Eigen::Vector3d direction_world;
};

/// `per_direction` segments, 1-2.5 long at depths 4-10, along each of `directions_world`,
/// wholly in view of `T_world_cam`, their endpoints with `sigma_px` noise. Segments shorter
/// than 40 px in the image are drawn again.
inline std::vector<SegmentAlong> segments_along(const Pose& T_world_cam,
                                                const std::vector<Eigen::Vector3d>& directions_world,
                                                int per_direction, double sigma_px, std::mt19937& rng) {
  std::uniform_real_distribution<double> ux(-2.5, 2.5), uy(-1.5, 1.5), uz(4.0, 10.0), len(1.0, 2.5);
  std::vector<SegmentAlong> out;
  for (const auto& d : directions_world) {
    int made = 0;
    while (made < per_direction) {
      const Eigen::Vector3d a = T_world_cam * Eigen::Vector3d(ux(rng), uy(rng), uz(rng));
      const Eigen::Vector3d b = a + len(rng) * d.normalized();
      Eigen::Vector2d xa, xb;
      if (!in_view(T_world_cam, a) || !in_view(T_world_cam, b) || !observe(T_world_cam, a, xa) ||
          !observe(T_world_cam, b, xb) || (xa - xb).norm() * kFocal < 40)
        continue;
      out.push_back({add_noise(xa, sigma_px, rng), add_noise(xb, sigma_px, rng), d.normalized()});
      ++made;
    }
  }
  return out;
}

}  // namespace pllvo::test
