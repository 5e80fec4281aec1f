#pragma once
// `pllvo run --source SRC`: the odometry over a live or recorded video source until the stream
// ends, the source stalls or fails, or the caller asks it to stop (Ctrl-C / SIGTERM in the CLI).
// Whatever ends the run, the outputs of what was computed are written (trajectory.tum,
// keyframes.tum, stats.json, map.ply), and the reason is reported.
#include <atomic>
#include <filesystem>
#include <functional>
#include <string>

#include "pllvo/io/sequence.h"
#include "pllvo/io/video_source.h"
#include "pllvo/vo/odometry_session.h"
#include "pllvo/vo/vo_config.h"

namespace pllvo::vo {

struct SourceRunOptions {
  std::filesystem::path out_dir;  ///< empty: write nothing
  bool stereo = true;             ///< use the second image when the source delivers one
  /// Live-rate logic (frames handed to the tracker as they arrive, dropped while it is busy; the
  /// tracker never waits for the keyframe worker). Default for cameras; a file is read as fast as
  /// the tracker goes unless this is set.
  bool realtime = false;
  size_t max_frames = 0;  ///< 0: until the stream ends
  /// Set from another thread (a signal handler's) to end the run cleanly after the current frame.
  const std::atomic<bool>* stop = nullptr;
  std::function<void(const std::string&)> progress;  ///< every config.run.progress_interval_s
  std::function<void(const TrackingView&)> on_frame;
};

struct SourceRunResult {
  RunSummary summary;
  /// end_of_stream, stopped, max_frames; or, when the source failed: stalled, bad_frame, truncated.
  std::string ended_by;
  std::string message;  ///< one line saying what happened (the source's error, naming the frame)
  bool failed() const { return ended_by == "stalled" || ended_by == "bad_frame" || ended_by == "truncated"; }
};

SourceRunResult run_source(io::VideoSource& source, const io::Calibration& calibration, const VoConfig& config,
                           const SourceRunOptions& options);

}  // namespace pllvo::vo
