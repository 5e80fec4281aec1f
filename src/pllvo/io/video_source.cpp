#include "pllvo/io/video_source.h"

#include <algorithm>
#include <cmath>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <thread>

#include <opencv2/videoio.hpp>

#include "pllvo/common/error.h"

namespace pllvo::io {

/// The reader thread's hand-over: one frame at a time, the reader waits until it is taken (a file
/// is read at the consumer's pace; a camera's driver drops frames meanwhile, as it does anyway).
struct VideoSource::Shared {
  std::mutex mutex;
  std::condition_variable changed;
  std::optional<GrabbedFrame> frame;
  bool ended = false;
  bool stop = false;
  std::exception_ptr failure;
  FrameGrabber grabber;
};

namespace {

bool is_device(const std::string& source) {
  return (!source.empty() && source.find_first_not_of("0123456789") == std::string::npos) ||
         source.rfind("/dev/", 0) == 0;
}

/// Microseconds: a file's frame times are whole milliseconds or finer, and rounding gives the
/// same double as an image folder's i / fps for a constant rate.
double round_to_us(double seconds) { return std::round(seconds * 1e6) / 1e6; }

}  // namespace

std::unique_ptr<VideoSource> VideoSource::open(const std::string& source, const VideoSourceOptions& options) {
  auto capture = std::make_shared<cv::VideoCapture>();
  const bool device = is_device(source);
  const bool opened = device && source.rfind("/dev/", 0) != 0 ? capture->open(std::stoi(source))
                                                                : capture->open(source);
  if (!opened || !capture->isOpened())
    throw InputError(source, "cannot open this video source (a file, a camera index or /dev/videoN, a GStreamer "
                             "pipeline or an image pattern such as img_%04d.png)");
  const bool pipeline = source.find('!') != std::string::npos;
  const bool live = device || (pipeline && source.find("filesrc") == std::string::npos);
  const double count = capture->get(cv::CAP_PROP_FRAME_COUNT);
  FrameGrabber grab = [capture, live](GrabbedFrame& out) {
    if (!capture->read(out.image)) return false;
    const double ms = capture->get(cv::CAP_PROP_POS_MSEC);
    if (!live && std::isfinite(ms) && ms >= 0) out.timestamp_s = round_to_us(ms / 1000.0);
    return true;
  };
  return std::make_unique<VideoSource>(source, std::move(grab), live, options,
                                       !live && count > 0 ? static_cast<size_t>(count) : 0);
}

VideoSource::VideoSource(std::string name, FrameGrabber grabber, bool live, const VideoSourceOptions& options,
                         size_t expected_frames)
    : name_(std::move(name)),
      live_(live),
      options_(options),
      expected_frames_(expected_frames),
      opened_(std::chrono::steady_clock::now()),
      shared_(std::make_shared<Shared>()) {
  if (options_.stereo_layout != "mono" && options_.stereo_layout != "side-by-side")
    throw InputError(name_, "unknown stereo layout '" + options_.stereo_layout + "' (mono or side-by-side)");
  if (!(options_.stall_timeout_s > 0)) throw InputError(name_, "the stall timeout must be positive");
  shared_->grabber = std::move(grabber);
  std::thread([s = shared_] {
    try {
      while (true) {
        GrabbedFrame f;
        const bool got = s->grabber(f);
        std::unique_lock<std::mutex> lock(s->mutex);
        if (!got) {
          s->ended = true;
          s->changed.notify_all();
          return;
        }
        s->changed.wait(lock, [&] { return !s->frame || s->stop; });
        if (s->stop) return;
        s->frame = std::move(f);
        s->changed.notify_all();
      }
    } catch (...) {
      std::lock_guard<std::mutex> lock(s->mutex);
      s->failure = std::current_exception();
      s->ended = true;
      s->changed.notify_all();
    }
  }).detach();  // a stalled read cannot be interrupted; the thread owns what it uses
}

VideoSource::~VideoSource() {
  std::lock_guard<std::mutex> lock(shared_->mutex);
  shared_->stop = true;
  shared_->changed.notify_all();
}

VideoSource::Status VideoSource::next(Frame& frame, const std::atomic<bool>* stop) {
  GrabbedFrame grabbed;
  {
    std::unique_lock<std::mutex> lock(shared_->mutex);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                                  std::chrono::duration<double>(options_.stall_timeout_s));
    while (!shared_->frame && !shared_->ended) {
      if (stop && *stop) return Status::kStopped;
      const auto now = std::chrono::steady_clock::now();
      if (now >= deadline) return Status::kStalled;
      shared_->changed.wait_until(lock, std::min(deadline, now + std::chrono::milliseconds(50)));
    }
    if (!shared_->frame) {
      if (shared_->failure) std::rethrow_exception(shared_->failure);
      return Status::kEnd;
    }
    grabbed = std::move(*shared_->frame);
    shared_->frame.reset();
    shared_->changed.notify_all();
  }
  frame = Frame{};
  frame.index = frames_read_++;
  frame.timestamp = grabbed.timestamp_s ? *grabbed.timestamp_s
                                        : std::chrono::duration<double>(std::chrono::steady_clock::now() - opened_).count();
  const std::string which = name_ + ": frame " + std::to_string(frame.index);
  if (grabbed.image.empty()) throw InputError(which + " is empty (a corrupt frame, or the source failed)");
  if (stereo()) {
    if (grabbed.image.cols % 2 != 0)
      throw InputError(which + " is " + std::to_string(grabbed.image.cols) +
                       " pixels wide: a side-by-side stereo frame has an even width");
    const int half = grabbed.image.cols / 2;
    frame.left = grabbed.image(cv::Rect(0, 0, half, grabbed.image.rows)).clone();
    frame.right = grabbed.image(cv::Rect(half, 0, half, grabbed.image.rows)).clone();
  } else {
    frame.left = grabbed.image;
  }
  return Status::kFrame;
}

}  // namespace pllvo::io
