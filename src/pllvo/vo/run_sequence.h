#pragma once
// `pllvo run`: a whole sequence through the odometry, with a progress line and the output
// files (trajectory.tum, keyframes.tum, stats.json, map.ply) written at the end.
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "pllvo/io/sequence.h"
#include "pllvo/vo/run_output.h"
#include "pllvo/vo/vo_config.h"

namespace pllvo::vo {

struct RunOptions {
  std::filesystem::path out_dir;  ///< empty: write nothing
  bool stereo = true;             ///< use cam1 when the sequence has one
  size_t first_frame = 0;
  size_t max_frames = 0;  ///< 0: to the end
  /// Receives a progress line every config.run.progress_interval_s of wall time.
  std::function<void(const std::string&)> progress;
};

struct RunSummary {
  size_t frames = 0;
  size_t tracked_frames = 0;
  size_t keyframes = 0;
  int resets = 0;
  double wall_seconds = 0;
  double frames_per_second = 0;
  bool stereo = false;
  std::vector<LostInterval> lost;
  io::Trajectory trajectory;  ///< tracked frames, T_world_cam0
  nlohmann::json stats;       ///< what stats.json holds
};

RunSummary run_sequence(const io::Sequence& sequence, const VoConfig& config, const RunOptions& options);

}  // namespace pllvo::vo
