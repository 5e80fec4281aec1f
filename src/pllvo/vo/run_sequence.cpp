#include "pllvo/vo/run_sequence.h"

#include <cstdio>

#include <spdlog/spdlog.h>

#include "pllvo/common/error.h"
#include "pllvo/vo/live_playback.h"

namespace pllvo::vo {
namespace {

std::string describe(const LostInterval& l) {
  char buf[128];
  std::snprintf(buf, sizeof buf, "frames %zu-%zu (t %.3f-%.3f s)", l.first_frame, l.last_frame, l.first_time,
                l.last_time);
  return buf;
}

}  // namespace

void RunOptions::choose_sensors(const io::Sequence& sequence, bool mono, bool rgbd) {
  stereo = !mono && !rgbd;
  depth = !mono;
  if (rgbd && !sequence.calibration().has_depth())
    throw InputError(sequence.root(), "--rgbd: the dataset has no depth images (TUM depth.txt, EuRoC cam0/depth/, an "
                                      "image folder's depth/)");
}

RunSummary run_sequence(const io::Sequence& sequence, const VoConfig& config, const RunOptions& options) {
  if (sequence.size() == 0) throw InputError(sequence.root(), "the sequence has no frames");
  if (options.first_frame >= sequence.size())
    throw InputError("first frame " + std::to_string(options.first_frame) + " is past the end (" +
                     std::to_string(sequence.size()) + " frames)");
  const size_t end = options.max_frames == 0 ? sequence.size()
                                             : std::min(sequence.size(), options.first_frame + options.max_frames);
  SessionOptions session_options;
  session_options.stereo = options.stereo;
  session_options.depth = options.depth;
  session_options.live = options.realtime;
  OdometrySession session(config, sequence.calibration(), session_options);
  if (options.on_frame)
    session.set_on_frame([&](const FrameRecord&, const TrackingView& view) { options.on_frame(view); });

  ProgressReport progress(config.run.progress_interval_s, options.progress);
  size_t done = 0;
  const auto track = [&](io::Frame& frame) {
    session.process(std::move(frame));
    progress.after_frame(session, ++done, end - options.first_frame);
  };
  const auto load = [&](size_t i) {
    io::Frame frame = sequence.frame(i);
    frame.index = i;
    return frame;
  };
  std::optional<LiveRunStats> replayed;
  if (options.realtime) {
    LivePlaybackConfig playback_config;
    playback_config.speed = options.speed;
    const LivePlaybackResult played =
        LivePlayback(playback_config).play(options.first_frame, end, sequence.timestamps(), load, track);
    replayed.emplace();
    replayed->speed = options.speed;
    replayed->dropped_frames = played.dropped;
    replayed->latency_s = summarize_latency(played.latency_s);
  } else {
    for (size_t i = options.first_frame; i < end; ++i) {
      io::Frame frame;
      {
        ScopedTimer t(session.stats(), "load");
        frame = load(i);
      }
      track(frame);
    }
  }
  session.finish();

  SessionSource source;
  source.root = sequence.root().string();
  source.format = sequence.format();
  source.ground_truth = sequence.ground_truth();
  RunSummary summary = session.summary(source, replayed);
  for (const auto& l : summary.lost) spdlog::warn("not tracked: {}", describe(l));
  if (summary.live && !summary.live->dropped_frames.empty())
    spdlog::warn("dropped (arrived while the tracker was busy): {} of {} frames", summary.live->dropped_frames.size(),
                 summary.frames);
  if (!options.out_dir.empty()) OdometrySession::save(summary, options.out_dir);
  return summary;
}

}  // namespace pllvo::vo
