// mapping.mono_align_to_origin end to end: monocular keyframes align their candidates to the
// keyframe where each track began, on noisy (low-light) frames only. A small rendered easy
// flight (synthetic_sequence.h), deterministic single-thread mode.
#include <unistd.h>

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "pllvo/io/sequence.h"
#include "pllvo/vo/run_sequence.h"
#include "synthetic_sequence.h"

namespace pllvo::vo {
namespace {

RunSummary run_mono(const std::string& preset, const VoConfig& config) {
  const auto dir = testing::rendered(testing::small_spec(preset, 3.0, false), "align_" + preset);
  const auto seq = io::open_sequence(dir);
  RunOptions options;
  options.first_frame = 20;  // cruising speed (see Initialisation.MonocularTwoView...)
  return run_sequence(*seq, config, options);
}

long long aligned(const RunSummary& s) { return testing::stats_count(s.stats, "aligned_candidates"); }
long long dropped(const RunSummary& s) { return testing::stats_count(s.stats, "alignment_dropped"); }

TEST(OriginAlignment, LowLightKeyframesAlignTheirCandidatesAndDropThoseThatDoNotAlign) {
  const RunSummary on = run_mono("easy_lowlight", testing::deterministic());
  VoConfig off_config = testing::deterministic();
  off_config.mapping.mono_align_to_origin = false;
  const RunSummary off = run_mono("easy_lowlight", off_config);
  std::printf("[ align ] low light: %lld candidates aligned, %lld dropped; ATE %.2f %% (off: %.2f %%), "
              "%d / %d keyframes\n",
              aligned(on), dropped(on), on.error ? on.error->percent_of_path : -1.0,
              off.error ? off.error->percent_of_path : -1.0, on.stats["keyframes"].get<int>(),
              off.stats["keyframes"].get<int>());
  EXPECT_EQ(on.tracked_frames, on.frames);
  EXPECT_GT(aligned(on), 100);
  EXPECT_GT(dropped(on), 0);
  EXPECT_EQ(aligned(off) + dropped(off), 0);
  const double rms_on = on.stats["per_frame"]["ba_rms_px"]["mean"].get<double>();
  const double rms_off = off.stats["per_frame"]["ba_rms_px"]["mean"].get<double>();
  std::printf("[ align ] bundle adjustment rms %.3f px (off: %.3f px)\n", rms_on, rms_off);
  // Aligned observations fit the geometry better (measured 0.407 against 0.432 px).
  EXPECT_LT(rms_on, rms_off);
  ASSERT_TRUE(on.error.has_value());
  EXPECT_LT(on.error->percent_of_path, 8.0);  // the bound of the monocular start test
}

TEST(OriginAlignment, NormalLightKeyframesKeepTheirTracks) {
  const RunSummary s = run_mono("easy_normal", testing::deterministic());
  EXPECT_EQ(s.tracked_frames, s.frames);
  EXPECT_EQ(aligned(s) + dropped(s), 0);  // image noise below mapping.mono_align_min_noise
  VoConfig always = testing::deterministic();
  always.mapping.mono_align_min_noise = 0;
  EXPECT_GT(aligned(run_mono("easy_normal", always)), 100);
}

}  // namespace
}  // namespace pllvo::vo
