// Live-rate playback: a tracker slower than the source loses frames, not time.
#include <chrono>
#include <thread>

#include <gtest/gtest.h>

#include "pllvo/vo/live_playback.h"

namespace pllvo::vo {
namespace {

std::vector<double> stamps_at(double rate_hz, size_t n) {
  std::vector<double> s(n);
  for (size_t i = 0; i < n; ++i) s[i] = static_cast<double>(i) / rate_hz;
  return s;
}

io::Frame frame_at(size_t i, const std::vector<double>& stamps) {
  io::Frame f;
  f.index = i;
  f.timestamp = stamps[i];
  return f;
}

TEST(LivePlayback, SlowConsumerDropsFramesAndRecordsLatency) {
  const auto stamps = stamps_at(100.0, 30);  // 10 ms apart, 0.29 s of input
  const auto load = [&](size_t i) { return frame_at(i, stamps); };
  const auto slow = [](io::Frame&) { std::this_thread::sleep_for(std::chrono::milliseconds(35)); };
  const LivePlaybackResult r = LivePlayback().play(0, stamps.size(), stamps, load, slow);
  // Every frame is either consumed or dropped, once.
  EXPECT_EQ(r.consumed.size() + r.dropped.size(), stamps.size());
  // At 35 ms a frame the consumer takes about every third or fourth frame.
  EXPECT_GE(r.dropped.size(), 15u);
  EXPECT_LE(r.consumed.size(), 14u);
  EXPECT_EQ(r.consumed.front(), 0u);
  EXPECT_EQ(r.consumed.back(), stamps.size() - 1);  // the newest frame is never left behind
  ASSERT_EQ(r.latency_s.size(), r.consumed.size());
  for (double l : r.latency_s) EXPECT_GE(l, 0.030);
  // The source never waits for the consumer: playback ends about when the input does.
  EXPECT_LT(r.wall_seconds, 0.29 + 0.2);
}

TEST(LivePlayback, FastConsumerGetsEveryFrameAtItsTime) {
  const auto stamps = stamps_at(50.0, 10);  // 20 ms apart
  const auto load = [&](size_t i) { return frame_at(i, stamps); };
  const auto fast = [](io::Frame&) {};
  const LivePlaybackResult r = LivePlayback().play(0, stamps.size(), stamps, load, fast);
  EXPECT_EQ(r.consumed.size(), stamps.size());
  EXPECT_TRUE(r.dropped.empty());
  EXPECT_GE(r.wall_seconds, 0.17);  // frames came at their timestamps, not at once
  const LatencySummary lat = summarize_latency(r.latency_s);
  EXPECT_LT(lat.mean, 0.015);
}

TEST(LivePlayback, ConsumerErrorStopsPlaybackAndIsRethrown) {
  const auto stamps = stamps_at(200.0, 20);
  const auto load = [&](size_t i) { return frame_at(i, stamps); };
  const auto failing = [](io::Frame& f) {
    if (f.index == 3) throw std::runtime_error("bad frame");
  };
  EXPECT_THROW(LivePlayback().play(0, stamps.size(), stamps, load, failing), std::runtime_error);
}

TEST(LivePlayback, RejectsNonPositiveSpeed) {
  LivePlaybackConfig c;
  c.speed = 0;
  EXPECT_ANY_THROW(LivePlayback{c});
}

TEST(LatencySummary, MeanP95Max) {
  std::vector<double> v;
  for (int i = 1; i <= 100; ++i) v.push_back(i);
  const LatencySummary s = summarize_latency(v);
  EXPECT_DOUBLE_EQ(s.mean, 50.5);
  EXPECT_DOUBLE_EQ(s.p95, 95.0);
  EXPECT_DOUBLE_EQ(s.max, 100.0);
}

}  // namespace
}  // namespace pllvo::vo
