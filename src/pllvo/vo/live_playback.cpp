#include "pllvo/vo/live_playback.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <mutex>
#include <thread>

#include "pllvo/common/error.h"
#include "pllvo/vo/frame_slot.h"

namespace pllvo::vo {
namespace {
using Clock = FrameSlot::Clock;
}  // namespace

LivePlayback::LivePlayback(LivePlaybackConfig config) : config_(config) {
  if (!(config_.speed > 0) || !std::isfinite(config_.speed))
    throw InputError("playback speed must be a positive number (got " + std::to_string(config_.speed) + ")");
}

LivePlaybackResult LivePlayback::play(size_t first, size_t end, const std::vector<double>& stamps, const Load& load,
                                      const Consume& consume) const {
  LivePlaybackResult result;
  if (first >= end) return result;
  if (end > stamps.size()) throw InputError("playback: frame range past the timestamps");
  FrameSlot slot;
  std::exception_ptr source_failure;
  std::atomic<bool> stop{false};
  const Clock::time_point start = Clock::now();
  const double t0 = stamps[first];

  std::thread source([&] {
    try {
      for (size_t i = first; i < end && !stop; ++i) {
        io::Frame frame = load(i);
        const auto due = start + std::chrono::duration_cast<Clock::duration>(
                                     std::chrono::duration<double>((stamps[i] - t0) / config_.speed));
        std::this_thread::sleep_until(due);
        const auto replaced = slot.put(std::move(frame), std::max(due, Clock::now()));
        // Only this thread writes `dropped`; the caller reads it after the join.
        if (replaced) result.dropped.push_back(*replaced);
      }
    } catch (...) {
      source_failure = std::current_exception();
    }
    slot.close();
  });

  std::exception_ptr consumer_failure;
  try {
    while (auto item = slot.take()) {
      consume(item->frame);
      result.consumed.push_back(item->frame.index);
      result.latency_s.push_back(std::chrono::duration<double>(Clock::now() - item->arrival).count());
    }
  } catch (...) {
    consumer_failure = std::current_exception();
    stop = true;
    while (slot.take()) {
    }  // let the source finish its current frame and close
  }
  source.join();
  result.wall_seconds = std::chrono::duration<double>(Clock::now() - start).count();
  if (consumer_failure) std::rethrow_exception(consumer_failure);
  if (source_failure) std::rethrow_exception(source_failure);
  std::sort(result.dropped.begin(), result.dropped.end());
  return result;
}

LatencySummary summarize_latency(std::vector<double> values) {
  LatencySummary s;
  if (values.empty()) return s;
  std::sort(values.begin(), values.end());
  double sum = 0;
  for (double v : values) sum += v;
  s.mean = sum / static_cast<double>(values.size());
  const size_t k = static_cast<size_t>(std::ceil(0.95 * static_cast<double>(values.size()))) - 1;
  s.p95 = values[std::min(k, values.size() - 1)];
  s.max = values.back();
  return s;
}

}  // namespace pllvo::vo
