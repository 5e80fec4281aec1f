#include "pllvo/vo/run_source.h"

#include <chrono>
#include <cstdio>
#include <optional>
#include <thread>

#include "pllvo/common/error.h"

namespace pllvo::vo {
namespace {

std::string stall_message(const io::VideoSource& source, double timeout_s) {
  char buf[160];
  std::snprintf(buf, sizeof buf, ": no frame for %.1f s after %zu frames (the source stalled)", timeout_s,
                source.frames_read());
  return source.name() + buf;
}

/// Reads the source into the session until something ends the run; says what did.
void feed(io::VideoSource& source, OdometrySession& session, double stall_timeout_s, const SourceRunOptions& options,
          const VoConfig& config, SourceRunResult& result) {
  using clock = std::chrono::steady_clock;
  const auto start = clock::now();
  ProgressReport progress(config.run.progress_interval_s, options.progress);
  size_t given = 0;
  std::optional<double> first_timestamp;
  // A recorded file replayed at live rate: each frame is handed over at its time, as a camera would.
  const bool pace = options.realtime && !source.live();
  while (true) {
    if (options.stop && *options.stop) {
      result.ended_by = "stopped";
      return;
    }
    if (options.max_frames && given >= options.max_frames) {
      result.ended_by = "max_frames";
      return;
    }
    io::Frame frame;
    try {
      switch (source.next(frame, options.stop)) {
        case io::VideoSource::Status::kFrame:
          break;
        case io::VideoSource::Status::kStopped:
          result.ended_by = "stopped";
          return;
        case io::VideoSource::Status::kStalled:
          result.ended_by = "stalled";
          result.message = stall_message(source, stall_timeout_s);
          return;
        case io::VideoSource::Status::kEnd:
          if (source.expected_frames() > 0 && source.frames_read() < source.expected_frames()) {
            result.ended_by = "truncated";
            result.message = source.name() + ": the stream ended after " + std::to_string(source.frames_read()) +
                             " of the " + std::to_string(source.expected_frames()) +
                             " frames its container states (a truncated or damaged file)";
          } else {
            result.ended_by = "end_of_stream";
          }
          return;
      }
      if (!session.stereo()) frame.right.release();
      if (pace) {
        if (!first_timestamp) first_timestamp = frame.timestamp;
        std::this_thread::sleep_until(start + std::chrono::duration_cast<clock::duration>(
                                                  std::chrono::duration<double>(frame.timestamp - *first_timestamp)));
      }
      if (options.realtime)
        session.push(std::move(frame));
      else
        session.process(std::move(frame));
    } catch (const InputError& e) {
      result.ended_by = "bad_frame";
      result.message = e.what();
      return;
    }
    progress.after_frame(session, ++given, 0);
  }
}

}  // namespace

SourceRunResult run_source(io::VideoSource& source, const io::Calibration& calibration, const VoConfig& config,
                           const SourceRunOptions& options) {
  if (source.stereo() && !calibration.stereo())
    throw InputError(source.name(), "a side-by-side stereo source needs a stereo calibration (--camera)");
  SessionOptions session_options;
  session_options.stereo = options.stereo && source.stereo();
  session_options.live = options.realtime;
  OdometrySession session(config, calibration, session_options);
  if (options.on_frame)
    session.set_on_frame([&](const FrameRecord&, const TrackingView& view) { options.on_frame(view); });
  SourceRunResult result;
  feed(source, session, source.stall_timeout_s(), options, config, result);
  session.finish();
  SessionSource from;
  from.root = source.name();
  from.format = "video";
  result.summary = session.summary(from);
  result.summary.stats["ended_by"] = result.ended_by;
  if (!result.message.empty()) result.summary.stats["end_message"] = result.message;
  if (!options.out_dir.empty()) OdometrySession::save(result.summary, options.out_dir);
  return result;
}

}  // namespace pllvo::vo
