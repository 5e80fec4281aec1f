#pragma once
// A camera driver's one-frame queue: put() replaces a frame nobody took yet, so the consumer
// always gets the newest frame and a slow consumer costs dropped frames, not growing latency.
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <optional>
#include <utility>

#include "pllvo/io/sequence.h"

namespace pllvo::vo {

class FrameSlot {
 public:
  using Clock = std::chrono::steady_clock;
  struct Item {
    io::Frame frame;
    Clock::time_point arrival;
  };

  /// Returns the index of the frame it replaced, if any.
  std::optional<size_t> put(io::Frame frame, Clock::time_point arrival) {
    std::lock_guard<std::mutex> lock(mutex_);
    std::optional<size_t> replaced;
    if (item_) replaced = item_->frame.index;
    item_ = Item{std::move(frame), arrival};
    ready_.notify_one();
    return replaced;
  }
  /// No more frames: take() returns nullopt once the slot is empty.
  void close() {
    std::lock_guard<std::mutex> lock(mutex_);
    closed_ = true;
    ready_.notify_all();
  }
  /// Blocks for the next frame; nullopt once closed and empty.
  std::optional<Item> take() {
    std::unique_lock<std::mutex> lock(mutex_);
    ready_.wait(lock, [&] { return item_.has_value() || closed_; });
    if (!item_) return std::nullopt;
    std::optional<Item> out = std::move(item_);
    item_.reset();
    return out;
  }

 private:
  std::mutex mutex_;
  std::condition_variable ready_;
  std::optional<Item> item_;
  bool closed_ = false;
};

}  // namespace pllvo::vo
