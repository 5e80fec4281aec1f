#pragma once
// `pllvo run`: a whole sequence through the odometry, with a progress line and the output
// files (trajectory.tum, keyframes.tum, stats.json, map.ply) written at the end.
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "pllvo/io/sequence.h"
#include "pllvo/vo/live_playback.h"
#include "pllvo/vo/odometry.h"
#include "pllvo/vo/odometry_session.h"
#include "pllvo/vo/run_output.h"
#include "pllvo/vo/trajectory_error.h"
#include "pllvo/vo/vo_config.h"

namespace pllvo::vo {

struct RunOptions {
  std::filesystem::path out_dir;  ///< empty: write nothing
  bool stereo = true;             ///< use cam1 when the sequence has one
  bool depth = true;              ///< else its depth images, when it has them (RGB-D)
  size_t first_frame = 0;
  size_t max_frames = 0;  ///< 0: to the end
  /// Receives a progress line every config.run.progress_interval_s of wall time.
  std::function<void(const std::string&)> progress;
  /// Called after every frame with the tracker's view of it (live viewer, report frames).
  std::function<void(const TrackingView&)> on_frame;
  /// Live-rate playback (LivePlayback): frames arrive at their timestamps / `speed` and the
  /// tracker never waits for the keyframe worker; a frame that arrives while the previous one
  /// still waits for the tracker is dropped. Off: every frame is processed, as fast as it can be.
  bool realtime = false;
  double speed = 1.0;

  /// The sensors as `pllvo run` and `pllvo bench` choose them: `mono`, the left camera only;
  /// `rgbd`, its depth images also beside a second camera (InputError naming the sequence's
  /// folder when it has none); neither, stereo with a second camera, else RGB-D with depth.
  void choose_sensors(const io::Sequence& sequence, bool mono, bool rgbd);
};

RunSummary run_sequence(const io::Sequence& sequence, const VoConfig& config, const RunOptions& options);

}  // namespace pllvo::vo
