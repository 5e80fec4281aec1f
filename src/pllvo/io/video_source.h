#pragma once
// Frames from anything OpenCV's VideoCapture opens: a video file, a camera (an index or
// /dev/videoN), a GStreamer pipeline, an image-sequence pattern (img_%04d.png). A reader thread
// pulls frames so that a source that stops delivering is noticed (stall timeout) instead of
// blocking the run; a stereo camera that delivers both images side by side in one frame is split.
#include <atomic>
#include <chrono>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include <opencv2/core.hpp>

#include "pllvo/io/sequence.h"

namespace pllvo::io {

struct VideoSourceOptions {
  /// "mono", or "side-by-side": the left image in the frame's left half, the right in its right half.
  std::string stereo_layout = "mono";
  /// A source that delivers no frame for this long (seconds) is reported as stalled.
  double stall_timeout_s = 5.0;
};

/// What one read of the stream gave.
struct GrabbedFrame {
  cv::Mat image;
  std::optional<double> timestamp_s;  ///< the source's own clock (file position); else arrival time is used
};
/// Reads the next frame; false at the end of the stream. Tests replace it with doubles.
using FrameGrabber = std::function<bool(GrabbedFrame&)>;

class VideoSource {
 public:
  enum class Status {
    kFrame,    ///< `frame` holds the next frame
    kEnd,      ///< the stream ended (end of file, or the device closed)
    kStalled,  ///< no frame within stall_timeout_s
    kStopped,  ///< `stop` was set while waiting
  };

  /// Opens `source` with cv::VideoCapture (a string of digits is a device index). InputError
  /// naming the source when it cannot be opened or the layout is unknown.
  static std::unique_ptr<VideoSource> open(const std::string& source, const VideoSourceOptions& options = {});

  /// `live`: a camera (frames arrive in real time; a slow tracker must drop them), not a file.
  /// `expected_frames`: the frame count the container states (0: unknown), to tell a truncated file.
  VideoSource(std::string name, FrameGrabber grabber, bool live, const VideoSourceOptions& options,
              size_t expected_frames = 0);
  ~VideoSource();
  VideoSource(const VideoSource&) = delete;
  VideoSource& operator=(const VideoSource&) = delete;

  /// The next frame: index counted from 0, timestamp the source's when it has one (else seconds
  /// since the source was opened), left (and right, side by side) as read: colour is converted by
  /// the odometry. A frame that is empty, or a side-by-side frame of odd width, is an InputError
  /// naming the frame.
  /// `stop` (optional) is looked at every 50 ms while waiting.
  Status next(Frame& frame, const std::atomic<bool>* stop = nullptr);

  const std::string& name() const { return name_; }
  bool live() const { return live_; }
  bool stereo() const { return options_.stereo_layout == "side-by-side"; }
  size_t frames_read() const { return frames_read_; }
  size_t expected_frames() const { return expected_frames_; }
  double stall_timeout_s() const { return options_.stall_timeout_s; }

 private:
  struct Shared;
  std::string name_;
  bool live_;
  VideoSourceOptions options_;
  size_t expected_frames_;
  size_t frames_read_ = 0;
  std::chrono::steady_clock::time_point opened_;
  std::shared_ptr<Shared> shared_;  ///< with the reader thread, which may outlive a stalled source
};

}  // namespace pllvo::io
