#pragma once
// The error of a run's trajectory against the sequence's ground truth (evo's APE, translation).
#include <optional>
#include <string>

#include "pllvo/io/trajectory.h"

namespace pllvo::vo {

/// Absolute trajectory error against the sequence's ground truth (evo's APE, translation).
struct TrajectoryError {
  std::string align;        ///< "se3" (stereo, metric) or "sim3" (mono, scale unknown)
  bool collinear_reference = false;  ///< straight-line ground truth: rotation about it not observable
  size_t matched_poses = 0;
  double rmse_m = 0;
  double max_m = 0;
  double path_length_m = 0;  ///< ground truth path over the matched poses
  double percent_of_path = 0;
  double scale = 1;          ///< Sim(3) scale applied (1 for se3)
};

/// APE of `estimate` against `reference` (SE3 alignment for stereo, Sim3 for mono); nullopt
/// when fewer than 3 poses match. A straight-line reference (evo refuses it) is aligned all the
/// same, flagged `collinear_reference`.
std::optional<TrajectoryError> trajectory_error(const io::Trajectory& estimate, const io::Trajectory& reference,
                                                bool metric_scale);

}  // namespace pllvo::vo
