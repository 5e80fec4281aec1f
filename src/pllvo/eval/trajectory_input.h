#pragma once
// Loading the two trajectories of an evaluation, with evo's pairing of file formats.
#include <filesystem>
#include <string_view>

#include "pllvo/io/trajectory.h"

namespace pllvo::eval {

/// Format of the reference. evo's subcommands: tum (both TUM), euroc (EuRoC ground-truth csv
/// reference, TUM estimate), kitti (both KITTI). automatic: each file by its content.
enum class TrajectoryFormat { tum, euroc, kitti, automatic };

TrajectoryFormat parse_trajectory_format(std::string_view name);  ///< tum|euroc|kitti|auto
std::string_view trajectory_format_name(TrajectoryFormat format);

struct TrajectoryPair {
  io::Trajectory ref;
  io::Trajectory est;
};

/// Reads both files (InputError naming file and line on bad input).
TrajectoryPair load_trajectories(const std::filesystem::path& est_file, const std::filesystem::path& ref_file,
                                 TrajectoryFormat ref_format);

}  // namespace pllvo::eval
