// The plain-scene rule (VoConfig::plain_scene): in a room of blank walls the few keyframe
// detections turn on stereo lines and line flow with aperture handling; in a textured scene the
// rule never fires. Rendered medium_lowtexture (the suite's spec, its first 2.5 s, full
// resolution) and easy_normal (half the EuRoC resolution), deterministic single-thread mode,
// with pllvo's SuperPoint: the rule counts a keyframe's detections, and ORB fills its quota with
// corners of the sensor noise on a blank wall.
#include <cstdio>

#include <gtest/gtest.h>

#include "pllvo/io/sequence.h"
#include "pllvo/vo/run_sequence.h"
#include "synthetic_sequence.h"

namespace pllvo::vo {
namespace {

long long count(const RunSummary& s, const std::string& name) { return testing::stats_count(s.stats, name); }

double stereo_lines_made(const RunSummary& s) {
  const auto& pf = s.stats["per_frame"];
  if (!pf.contains("kf_stereo_lines")) return 0;
  return pf["kf_stereo_lines"]["mean"].get<double>() * pf["kf_stereo_lines"]["count"].get<double>();
}

VoConfig superpoint() {
  VoConfig c = testing::deterministic();
  c.frontend.type = "superpoint";
  c.frontend.superpoint_weights = PLLVO_SOURCE_DIR "/models/pllvo_superpoint_v1.safetensors";
  c.mapping.matcher = "mnn";
  return c;
}

VoConfig rule_off() {
  VoConfig c = superpoint();
  c.plain_scene.max_keyframe_features = 0;
  c.plain_scene.max_tracked_points = 0;
  return c;
}

void print(const char* name, const RunSummary& s) {
  std::printf("[ plain scene ] %s: %zu/%zu frames, %lld plain keyframes, %lld plain line frames, %.0f stereo lines, "
              "ATE %.4f m = %.2f %%\n",
              name, s.tracked_frames, s.frames, count(s, "plain_scene_keyframes"), count(s, "plain_scene_line_frames"),
              stereo_lines_made(s), s.error ? s.error->rmse_m : -1.0, s.error ? s.error->percent_of_path : -1.0);
}

TEST(PlainScene, BlankWallsTurnOnStereoLinesAndApertureHandling) {
  synth::SequenceSpec spec = synth::preset("medium_lowtexture");
  spec.duration_s = 2.5;
  spec.camera.stereo = true;
  const auto dir = testing::rendered(spec, "plain_room");
  const auto seq = io::open_sequence(dir);
  const RunSummary on = run_sequence(*seq, superpoint(), {});
  const RunSummary off = run_sequence(*seq, rule_off(), {});
  print("rule on", on);
  print("rule off", off);
  EXPECT_GT(count(on, "plain_scene_keyframes"), 5);
  EXPECT_GT(count(on, "plain_scene_line_frames"), 5);
  EXPECT_GT(stereo_lines_made(on), 5);
  EXPECT_EQ(count(off, "plain_scene_keyframes"), 0);
  EXPECT_EQ(count(off, "plain_scene_line_frames"), 0);
  EXPECT_EQ(stereo_lines_made(off), 0);
  ASSERT_TRUE(on.error && off.error);
  EXPECT_EQ(on.tracked_frames, on.frames);
  // Measured over the first 2.5 s, whose middle second shows a blank wall, a door and a floor
  // edge: 0.086 m = 5.16 % with the rule, 0.181 m = 10.9 % without it (2-core AMD EPYC, the
  // stereo window without fixed older keyframes; with five of them 4.97 %; on an Intel Xeon
  // before that 3.5 % and 9.3 %). The ratio below is the rule's effect.
  EXPECT_LT(on.error->percent_of_path, 6.0);
  EXPECT_LT(on.error->rmse_m, 0.6 * off.error->rmse_m);
}

TEST(PlainScene, TexturedScenesNeverTurnItOn) {
  const auto dir = testing::rendered(testing::small_spec("easy_normal", 3.0, true), "plain_textured");
  const auto seq = io::open_sequence(dir);
  const RunSummary s = run_sequence(*seq, superpoint(), {});
  print("textured", s);
  EXPECT_EQ(count(s, "plain_scene_keyframes"), 0);
  EXPECT_EQ(count(s, "plain_scene_line_frames"), 0);
  EXPECT_EQ(s.tracked_frames, s.frames);
}

}  // namespace
}  // namespace pllvo::vo
