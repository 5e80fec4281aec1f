#pragma once
// Frames of a sequence, read in order, optionally loaded ahead on a thread of their own.
//
// Decoding a 752x480 PNG pair costs ~10 ms, a fifth of a frame's budget at 20 frames/s, and the
// tracking thread used to do it itself. With `depth` > 0 a loader thread keeps up to `depth`
// frames decoded ahead of the consumer, so that the decoding overlaps the tracking when the
// machine has a core to spare. The frames and their order are the same either way; an
// unreadable frame throws its InputError from `next()` when the consumer reaches it, never
// earlier, so a run stops at the same frame with the same message.
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <mutex>
#include <thread>

#include "pllvo/io/sequence.h"

namespace pllvo::io {

class FramePrefetcher {
 public:
  /// Frames [first, end) of `sequence`, which must outlive this object. depth 0: each frame is
  /// loaded by next() on the caller's thread (no thread is started).
  FramePrefetcher(const Sequence& sequence, size_t first, size_t end, size_t depth);
  ~FramePrefetcher();
  FramePrefetcher(const FramePrefetcher&) = delete;
  FramePrefetcher& operator=(const FramePrefetcher&) = delete;

  /// True while frames are left (false after a frame that failed to load).
  bool has_next() const { return next_index_ < end_; }
  /// The next frame (its `index` set); rethrows the error of loading it. std::out_of_range
  /// when no frame is left.
  Frame next();

 private:
  struct Slot {
    Frame frame;
    std::exception_ptr error;
  };
  Slot load(size_t i) const;
  void loader_loop(size_t first);

  const Sequence& sequence_;
  const size_t end_;
  const size_t depth_;
  size_t next_index_;  ///< the consumer's next frame

  std::mutex mutex_;
  std::condition_variable space_or_stop_;  ///< the loader waits for room in the queue
  std::condition_variable ready_;          ///< the consumer waits for a loaded frame
  std::deque<Slot> queue_;                 ///< loaded frames, in order
  bool stop_ = false;
  std::thread loader_;
};

}  // namespace pllvo::io
