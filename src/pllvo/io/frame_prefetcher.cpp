#include "pllvo/io/frame_prefetcher.h"

#include <stdexcept>
#include <string>

namespace pllvo::io {

FramePrefetcher::FramePrefetcher(const Sequence& sequence, size_t first, size_t end, size_t depth)
    : sequence_(sequence), end_(end), depth_(depth), next_index_(first) {
  if (depth_ > 0 && first < end_) loader_ = std::thread([this, first] { loader_loop(first); });
}

FramePrefetcher::~FramePrefetcher() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  space_or_stop_.notify_all();
  if (loader_.joinable()) loader_.join();
}

FramePrefetcher::Slot FramePrefetcher::load(size_t i) const {
  Slot slot;
  try {
    slot.frame = sequence_.frame(i);
    slot.frame.index = i;
  } catch (...) {
    slot.error = std::current_exception();
  }
  return slot;
}

void FramePrefetcher::loader_loop(size_t first) {
  // It stops after a frame that failed to load: the consumer stops there too.
  for (size_t i = first; i < end_; ++i) {
    {
      std::unique_lock lock(mutex_);
      space_or_stop_.wait(lock, [this] { return stop_ || queue_.size() < depth_; });
      if (stop_) return;
    }
    Slot slot = load(i);
    const bool failed = slot.error != nullptr;
    {
      std::lock_guard lock(mutex_);
      queue_.push_back(std::move(slot));
    }
    ready_.notify_one();
    if (failed) return;
  }
}

Frame FramePrefetcher::next() {
  if (!has_next())
    throw std::out_of_range("FramePrefetcher::next: no frame left (end " + std::to_string(end_) + ")");
  Slot slot;
  if (depth_ == 0) {
    slot = load(next_index_);
  } else {
    std::unique_lock lock(mutex_);
    ready_.wait(lock, [this] { return !queue_.empty(); });
    slot = std::move(queue_.front());
    queue_.pop_front();
    lock.unlock();
    space_or_stop_.notify_one();
  }
  ++next_index_;
  if (slot.error) {
    next_index_ = end_;  // nothing follows a failed frame (the loader has stopped)
    std::rethrow_exception(slot.error);
  }
  return std::move(slot.frame);
}

}  // namespace pllvo::io
