#pragma once
// Live-rate playback: frames are handed to a consumer at their timestamps, from a source thread,
// as a camera driver with a one-frame queue hands them over. A live camera does not wait for the
// tracker: a frame still waiting in the queue when the next one arrives is replaced by it and
// counted as dropped, so the tracker always gets the newest frame and its latency stays bounded.
//
// The source and the consumer are functions, so the same logic serves a dataset replayed at its
// own rate (`pllvo run --realtime`), a live source, and tests with slow doubles.
#include <cstddef>
#include <functional>
#include <vector>

#include "pllvo/io/sequence.h"

namespace pllvo::vo {

struct LivePlaybackConfig {
  /// Playback speed: frame k arrives (t_k - t_first) / speed seconds after the start.
  double speed = 1.0;
};

/// What playback measured: which frames the consumer got, which were dropped, and each
/// consumed frame's latency (arrival in the queue to the consumer's return).
struct LivePlaybackResult {
  std::vector<size_t> consumed;       ///< frame indices, in order
  std::vector<size_t> dropped;        ///< frame indices that arrived and were replaced unread
  std::vector<double> latency_s;      ///< one per consumed frame
  double wall_seconds = 0;
};

class LivePlayback {
 public:
  /// Loads frame `i` (its index and timestamp set); runs on the source thread, ahead of the
  /// frame's arrival time, as a camera's exposure and read-out happen before the driver's hand-over.
  using Load = std::function<io::Frame(size_t i)>;
  /// Processes one frame; runs on the caller's thread of play().
  using Consume = std::function<void(io::Frame& frame)>;

  explicit LivePlayback(LivePlaybackConfig config = {});

  /// Plays frames [first, end) with timestamps `stamps` (indexed by frame), returns when the last
  /// arrived frame has been consumed. An exception from `load` or `consume` stops playback and
  /// is rethrown here after the source thread has been joined.
  LivePlaybackResult play(size_t first, size_t end, const std::vector<double>& stamps, const Load& load,
                          const Consume& consume) const;

 private:
  LivePlaybackConfig config_;
};

/// Mean, 95th percentile and maximum of `values` (0s when empty).
struct LatencySummary {
  double mean = 0, p95 = 0, max = 0;
};
LatencySummary summarize_latency(std::vector<double> values);

}  // namespace pllvo::vo
