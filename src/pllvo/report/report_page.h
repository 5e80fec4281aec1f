#pragma once
// `pllvo report RUN_DIR`: one self-contained HTML page about a run (no scripts, no network):
// trajectory top and side views against ground truth, error over time, x/y/z and
// roll/pitch/yaw against ground truth (the paper's Figure 7), per-module timing bars and a few
// frames with the tracked points and lines drawn (embedded PNGs).
#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "pllvo/io/trajectory.h"

namespace pllvo::report {

struct ReportInput {
  std::string title;
  io::Trajectory estimate;                   ///< T_world_cam0, tracked frames
  std::optional<io::Trajectory> ground_truth;  ///< T_world_cam0
  bool metric_scale = true;                  ///< stereo: SE3 alignment; mono: Sim3
  nlohmann::json stats;                      ///< the run's stats.json
  std::vector<std::filesystem::path> frames; ///< annotated frames (PNG)
  std::string note;                          ///< shown under the title (e.g. why there is no ground truth)
};

/// The series the plots show: the estimate aligned onto the ground truth (when there is
/// one), sampled at the estimate's matched stamps.
struct PlotSeries {
  std::vector<double> t;                          ///< seconds from the first estimate pose
  std::vector<Eigen::Vector3d> est_xyz, gt_xyz;  ///< gt empty without ground truth
  std::vector<Eigen::Vector3d> est_rpy, gt_rpy;  ///< degrees, roll-pitch-yaw (ZYX), unwrapped
  std::vector<double> error_m;                    ///< APE translation per pose
  double ate_rmse_m = NAN;
  double scale = 1;                               ///< Sim(3) scale applied to the estimate
  std::string align;                              ///< "se3", "sim3" or "none"
};

/// Aligns (Umeyama SE3 / Sim3 over all matched poses, as `pllvo eval`) and samples. Without
/// ground truth or with too few matches the estimate is shown as it is.
PlotSeries plot_series(const io::Trajectory& estimate, const std::optional<io::Trajectory>& ground_truth,
                       bool metric_scale);

/// Roll, pitch, yaw (degrees) of R = Rz(yaw) Ry(pitch) Rx(roll).
Eigen::Vector3d roll_pitch_yaw_deg(const Eigen::Matrix3d& R);
/// The axes (0 x, 1 y, 2 z) ordered by how far `points` spread along them (max - min), largest
/// first: the trajectory plots show the plane of the first two (KITTI: x-z) and the first with the third.
std::array<int, 3> axes_by_extent(const std::vector<Eigen::Vector3d>& points);
/// Adds multiples of 360 so that consecutive angles differ by less than 180 degrees.
void unwrap_degrees(std::vector<double>& angles);

std::string base64_encode(const std::string& bytes);

/// Reads RUN_DIR: trajectory.tum, stats.json and frames/*.png. Ground truth: `ground_truth_file`
/// (TUM, T_world_cam0) when given, else the dataset stats.json names, when it can be opened.
/// InputError naming the file when trajectory.tum or stats.json is missing or malformed.
ReportInput load_run(const std::filesystem::path& run_dir, const std::filesystem::path& ground_truth_file = {});

std::string render_report(const ReportInput& input);

/// load_run + render_report, written to `out` (default RUN_DIR/report.html); returns the path.
std::filesystem::path write_report(const std::filesystem::path& run_dir, const std::filesystem::path& out = {},
                                   const std::filesystem::path& ground_truth_file = {});

}  // namespace pllvo::report
