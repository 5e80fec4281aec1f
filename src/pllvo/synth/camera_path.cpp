#include "pllvo/synth/camera_path.h"

#include <cmath>

#include "pllvo/geometry/pose.h"
#include "pllvo/synth/random.h"

namespace pllvo::synth {

namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr double kCalibrationWindow = 120.0;  // seconds the mean rates are solved over

double sum_waves(const std::vector<DronePath::Wave>& waves, double t, double rate) {
  double s = 0;
  for (const auto& w : waves) s += w.amplitude * std::sin(rate * w.omega * t + w.phase);
  return s;
}

double sum_waves_dot(const std::vector<DronePath::Wave>& waves, double t, double rate) {
  double s = 0;
  for (const auto& w : waves) s += w.amplitude * rate * w.omega * std::cos(rate * w.omega * t + w.phase);
  return s;
}

/// `count` waves whose amplitudes sum to `total`, base period `period_s`, frequency ratios
/// near the golden ratio's powers (incommensurate, so the motion does not repeat).
std::vector<DronePath::Wave> make_waves(Random& rng, int count, double total, double period_s) {
  std::vector<DronePath::Wave> waves;
  double sum = 0;
  for (int k = 0; k < count; ++k) {
    const double ratio = std::pow(1.618, k) * rng.uniform(0.85, 1.15);
    waves.push_back({rng.uniform(0.3, 1.0) / ratio, 2 * M_PI / period_s * ratio, rng.uniform(0, 2 * M_PI)});
    sum += waves.back().amplitude;
  }
  for (auto& w : waves) w.amplitude *= total / sum;
  return waves;
}

/// Rate r with f(r) = target for f roughly proportional to r (mean speed or turn rate of a
/// time-scaled path): fixed-point iterations r <- r * target / f(r).
template <typename F>
double solve_rate(F f, double target) {
  if (target <= 0) return 0;
  double r = 1.0;
  for (int it = 0; it < 8; ++it) {
    const double value = f(r);
    if (value <= 1e-12) return r;
    r = std::clamp(r * target / value, 1e-3, 1e3);
  }
  return r;
}

}  // namespace

Eigen::Vector3d CameraPath::velocity(double t) const {
  constexpr double h = 1e-4;
  return (pose(t + h).translation() - pose(t - h).translation()) / (2 * h);
}

Eigen::Isometry3d ConstantVelocityPath::pose(double t) const {
  Eigen::Isometry3d T = T0_;
  T.translation() += v_ * t;
  if (w_.norm() > 0) T.linear() = T0_.linear() * Eigen::AngleAxisd(w_.norm() * t, w_.normalized()).toRotationMatrix();
  return T;
}

Eigen::Matrix3d DronePath::attitude(double yaw, double pitch, double roll) {
  // Camera axes (x right, y down, z forward) when yaw = pitch = roll = 0: looking along world x.
  Eigen::Matrix3d base;
  base << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  return (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(-pitch, Eigen::Vector3d::UnitY()))
             .toRotationMatrix() *
         base * Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

DronePath::DronePath(const MotionSpec& m, const Scene& scene, uint64_t seed) {
  Random rng(derive_seed(seed, 0x7061746866ULL));
  const Box3& box = scene.free_space;
  centre_ = 0.5 * (box.min + box.max);
  const Eigen::Vector3d half = 0.5 * (box.max - box.min);
  const double shake = std::min(m.shake_m, 0.3 * half.minCoeff());
  for (int a = 0; a < 3; ++a) {
    // Periods differ per axis so the path fills the box instead of tracing a line.
    pos_[a] = make_waves(rng, 3, std::max(0.0, half[a] - shake) * 0.98, rng.uniform(16, 26));
    pos_shake_[a] = make_waves(rng, 2, shake, 1.0 / m.shake_hz);
  }
  rot_[0] = make_waves(rng, 3, m.yaw_swing_deg * kDeg, rng.uniform(14, 20));
  rot_[1] = make_waves(rng, 3, m.pitch_deg * kDeg, rng.uniform(9, 13));
  rot_[2] = make_waves(rng, 3, m.roll_deg * kDeg, rng.uniform(7, 11));
  for (int a = 0; a < 3; ++a) rot_shake_[a] = make_waves(rng, 2, m.shake_deg * kDeg, 1.0 / m.shake_hz);

  if (scene.has_preferred_yaw) {
    yaw0_ = scene.preferred_yaw + (rng.chance(0.5) ? M_PI : 0.0);
    yaw_drift_ = 0;
  } else {
    yaw0_ = rng.uniform(-M_PI, M_PI);
    yaw_drift_ = rng.sign() * m.yaw_drift * m.mean_angular_rate;
  }

  // Solve the time scales over a long window so that short sequences keep the same flight.
  pos_rate_ = solve_rate(
      [&](double r) {
        pos_rate_ = r;
        return path_stats(*this, 0, kCalibrationWindow, 20).mean_speed;
      },
      m.mean_speed);
  rot_rate_ = solve_rate(
      [&](double r) {
        rot_rate_ = r;
        return path_stats(*this, 0, kCalibrationWindow, 20).mean_angular_rate;
      },
      m.mean_angular_rate);
}

Eigen::Vector3d DronePath::position(double t) const {
  Eigen::Vector3d p = centre_;
  for (int a = 0; a < 3; ++a) p[a] += sum_waves(pos_[a], t, pos_rate_) + sum_waves(pos_shake_[a], t, 1.0);
  return p;
}

Eigen::Vector3d DronePath::velocity(double t) const {
  Eigen::Vector3d v;
  for (int a = 0; a < 3; ++a) v[a] = sum_waves_dot(pos_[a], t, pos_rate_) + sum_waves_dot(pos_shake_[a], t, 1.0);
  return v;
}

Eigen::Vector3d DronePath::angles(double t) const {
  Eigen::Vector3d a;
  for (int k = 0; k < 3; ++k) a[k] = sum_waves(rot_[k], t, rot_rate_) + sum_waves(rot_shake_[k], t, 1.0);
  a[0] += yaw0_ + yaw_drift_ * t;
  return a;
}

Eigen::Isometry3d DronePath::pose(double t) const {
  const Eigen::Vector3d a = angles(t);
  return geometry::make_pose(attitude(a[0], a[1], a[2]), position(t));
}

PathStats path_stats(const CameraPath& path, double t0, double t1, double hz) {
  PathStats s;
  const int n = std::max(1, static_cast<int>(std::ceil((t1 - t0) * hz)));
  const double dt = (t1 - t0) / n;
  Eigen::Isometry3d prev = path.pose(t0);
  for (int i = 1; i <= n; ++i) {
    const double t = t0 + i * dt;
    const Eigen::Isometry3d cur = path.pose(t);
    s.mean_speed += (cur.translation() - prev.translation()).norm() / dt;
    const double w = geometry::rotation_angle(prev.linear().transpose() * cur.linear()) / dt;
    s.mean_angular_rate += w;
    s.max_angular_rate = std::max(s.max_angular_rate, w);
    prev = cur;
  }
  s.mean_speed /= n;
  s.mean_angular_rate /= n;
  return s;
}

}  // namespace pllvo::synth
