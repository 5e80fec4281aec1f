#pragma once
// Timestamped trajectories and their file formats (TUM, EuRoC ground-truth csv, KITTI).
#include <filesystem>
#include <vector>

#include <Eigen/Geometry>

namespace pllvo::io {

/// Poses T_world_x with timestamps in seconds (KITTI: none -> empty `stamps`).
struct Trajectory {
  std::vector<double> stamps;
  std::vector<Eigen::Isometry3d, Eigen::aligned_allocator<Eigen::Isometry3d>> poses;

  size_t size() const { return poses.size(); }
  bool empty() const { return poses.empty(); }
  bool has_stamps() const { return stamps.size() == poses.size() && !poses.empty(); }
  void push_back(double t, const Eigen::Isometry3d& T) {
    stamps.push_back(t);
    poses.push_back(T);
  }
};

/// TUM: `t tx ty tz qx qy qz qw` per line, `#` comments. Follows evo's reader exactly:
/// single-space separated, 8 fields, quaternions normalised (see eval testvectors README).
Trajectory read_tum(const std::filesystem::path& file);
/// Writes with 17 significant digits (round-trips doubles); creates the parent folder.
void write_tum(const Trajectory& traj, const std::filesystem::path& file);

/// EuRoC state_groundtruth csv: ns, p xyz, q wxyz, ... (extra columns ignored).
/// Stamps are double(ns)/1e9 like evo. Poses are T_world_body; pass `T_body_cam`
/// to get T_world_cam.
Trajectory read_euroc_csv(const std::filesystem::path& file,
                          const Eigen::Isometry3d* T_body_cam = nullptr);

/// KITTI: 12 numbers per line, row-major [R|t]; no stamps. Matrices used as they are.
Trajectory read_kitti(const std::filesystem::path& file);
void write_kitti(const Trajectory& traj, const std::filesystem::path& file);

/// Picks the reader by content: KITTI (12 numbers), EuRoC csv (commas), else TUM.
Trajectory read_trajectory(const std::filesystem::path& file);

/// Quaternion (any norm, either sign) to rotation, as evo's quaternion_matrix does.
Eigen::Matrix3d rotation_from_quaternion(double qw, double qx, double qy, double qz);

}  // namespace pllvo::io
