#include "pllvo/eval/trajectory_input.h"

#include <string>

#include "pllvo/common/error.h"

namespace pllvo::eval {

TrajectoryFormat parse_trajectory_format(std::string_view name) {
  if (name == "tum") return TrajectoryFormat::tum;
  if (name == "euroc") return TrajectoryFormat::euroc;
  if (name == "kitti") return TrajectoryFormat::kitti;
  if (name == "auto") return TrajectoryFormat::automatic;
  throw InputError("unknown trajectory format '" + std::string(name) + "' (use tum, euroc, kitti or auto)");
}

std::string_view trajectory_format_name(TrajectoryFormat format) {
  switch (format) {
    case TrajectoryFormat::tum: return "tum";
    case TrajectoryFormat::euroc: return "euroc";
    case TrajectoryFormat::kitti: return "kitti";
    case TrajectoryFormat::automatic: return "auto";
  }
  return "auto";
}

TrajectoryPair load_trajectories(const std::filesystem::path& est_file, const std::filesystem::path& ref_file,
                                 TrajectoryFormat ref_format) {
  TrajectoryPair pair;
  switch (ref_format) {
    case TrajectoryFormat::tum:
      pair.ref = io::read_tum(ref_file);
      pair.est = io::read_tum(est_file);
      break;
    case TrajectoryFormat::euroc:  // evo's euroc subcommand: the estimate is always TUM
      pair.ref = io::read_euroc_csv(ref_file);
      pair.est = io::read_tum(est_file);
      break;
    case TrajectoryFormat::kitti:
      pair.ref = io::read_kitti(ref_file);
      pair.est = io::read_kitti(est_file);
      break;
    case TrajectoryFormat::automatic:
      pair.ref = io::read_trajectory(ref_file);
      pair.est = io::read_trajectory(est_file);
      break;
  }
  return pair;
}

}  // namespace pllvo::eval
