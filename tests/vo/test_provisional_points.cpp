// Provisional points (pose.provisional_points): a tracker that cannot wait for the keyframe in
// flight (live input) poses a starving frame on its candidates too, triangulated from their
// keyframe views and the latest tracked frame. Checked deterministically in the single thread
// with keyframes that come as late as a busy worker's would (only every 0.75 s, no point or
// line rule), on a dark, noisy synthetic flight (medium_lowlight at 376 x 240) against its
// ground truth; and offline input, which waits, never uses them.
#include <gtest/gtest.h>

#include "pllvo/vo/run_sequence.h"
#include "synthetic_sequence.h"

namespace pllvo::vo {
namespace {

/// Keyframes only by time, 0.75 s apart, and a tracker that never waits: a monocular map runs
/// short of points between keyframes as it does at live rate on a slow machine.
VoConfig late_keyframes(bool provisional) {
  VoConfig c = testing::deterministic();
  c.keyframes.use_point_trigger = false;
  c.keyframes.use_line_trigger = false;
  c.keyframes.max_interval_s = 0.75;
  c.keyframes.min_interval_s = 0.75;
  c.run.wait_when_starving = false;
  c.pose.provisional_points = provisional;
  return c;
}

RunSummary run_mono(const VoConfig& config) {
  const auto seq = io::open_sequence(testing::rendered(testing::small_spec("medium_lowlight", 6.0, false), "prov"));
  RunOptions options;
  options.stereo = false;
  return run_sequence(*seq, config, options);
}

void print(const char* what, const RunSummary& s) {
  std::printf("[ provisional points ] %s: %zu of %zu frames tracked, %d resets, %lld frames posed with provisional "
              "points, Sim3 ATE %.2f %%\n",
              what, s.tracked_frames, s.frames, s.resets,
              testing::stats_count(s.stats, "provisional_point_frames"),
              s.error ? s.error->percent_of_path : -1.0);
}

TEST(ProvisionalPoints, HoldAMonocularMapWhoseKeyframesComeLate) {
  const RunSummary with = run_mono(late_keyframes(true));
  const RunSummary without = run_mono(late_keyframes(false));
  print("with", with);
  print("without", without);
  EXPECT_GT(testing::stats_count(with.stats, "provisional_point_frames"), 10);
  EXPECT_EQ(testing::stats_count(without.stats, "provisional_point_frames"), 0);
  ASSERT_TRUE(with.error.has_value());
  ASSERT_TRUE(without.error.has_value());
  // Measured (ORB, this half-resolution flight): with them 121 of 121 frames tracked, 71 posed
  // with provisional points, 6.97 %; without 121 of 121, 9.06 %. Where a map runs out of points
  // they also keep it (docs/results.md); here they make the starving frames' poses better.
  EXPECT_GE(with.tracked_frames, without.tracked_frames);
  EXPECT_LE(with.resets, without.resets);
  EXPECT_LT(with.error->percent_of_path, 0.9 * without.error->percent_of_path);
}

TEST(ProvisionalPoints, OfflineInputWaitsAndNeverUsesThem) {
  VoConfig config = late_keyframes(true);
  config.run.wait_when_starving = true;
  const RunSummary offline = run_mono(config);
  config.pose.provisional_points = false;
  const RunSummary off = run_mono(config);
  print("offline", offline);
  EXPECT_EQ(testing::stats_count(offline.stats, "provisional_point_frames"), 0);
  ASSERT_TRUE(offline.error.has_value());
  ASSERT_TRUE(off.error.has_value());
  // The key changes nothing offline: the same trajectory to the last digit.
  EXPECT_EQ(offline.tracked_frames, off.tracked_frames);
  EXPECT_EQ(offline.error->rmse_m, off.error->rmse_m);
}

}  // namespace
}  // namespace pllvo::vo
