#pragma once
// Small scenes and generators shared by the synth tests.
#include <memory>

#include "pllvo/synth/camera_path.h"
#include "pllvo/synth/generator.h"
#include "pllvo/synth/layout.h"
#include "pllvo/synth/texture.h"

namespace pllvo::synth::testing {

/// A spec without noise or blur unless asked, short, EuRoC camera.
inline SequenceSpec quiet_spec(double duration = 1.0) {
  SequenceSpec spec;
  spec.name = "test";
  spec.duration_s = duration;
  spec.sensor.motion_blur = false;
  return spec;
}

/// A 4 x 3 m checkerboard wall (squares `square` m, 320 texels/m) in the plane y = 2,
/// facing -y (towards the origin), centred at x = 0, z = 1.5.
inline Quad add_checker_wall(SceneBuilder& b, double square = 0.1, double y = 2.0) {
  const Eigen::Vector3d centre(0, y, 1.5);
  const int q = b.add_facing(centre, -Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ(), 4.0, 3.0,
                             textures::checker({4.0, 3.0, 320}, square));
  return b.scene().quads[q];
}

inline Scene checker_scene(double square = 0.1) {
  SceneBuilder b;
  add_checker_wall(b, square);
  Scene s = b.finish();
  s.free_space.min = s.free_space.max = Eigen::Vector3d(0, 0, 1.5);
  return s;
}

/// Camera at (x, 0, 1.5) looking along +y (at the wall), with small extra yaw/pitch/roll (rad).
inline Eigen::Isometry3d camera_facing_wall(double x = 0, double yaw = 0, double pitch = 0, double roll = 0) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = DronePath::attitude(M_PI / 2 + yaw, pitch, roll);
  T.translation() = Eigen::Vector3d(x, 0, 1.5);
  return T;
}

/// Inner checker corners of a wall built by add_checker_wall, in the world frame.
inline std::vector<Eigen::Vector3d> checker_corners(const Quad& wall, double square) {
  std::vector<Eigen::Vector3d> pts;
  const double w = wall.u.norm(), h = wall.v.norm();
  for (double s = square; s < w - 1e-9; s += square)
    for (double t = square; t < h - 1e-9; t += square) pts.push_back(wall.point(s / w, t / h));
  return pts;
}

/// The medium_normal room seen from a fixed pose in the middle of its free space.
inline Generator static_room(SequenceSpec spec, double yaw = 0.3) {
  Scene scene = build_scene(spec.scene, spec.seed);
  const Eigen::Vector3d c = 0.5 * (scene.free_space.min + scene.free_space.max);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = DronePath::attitude(yaw, -0.1, 0.0);
  T.translation() = c;
  return Generator(std::move(spec), std::move(scene), std::make_shared<StaticPath>(T));
}

}  // namespace pllvo::synth::testing
