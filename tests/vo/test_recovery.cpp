// Tracking loss and recovery on a synthetic stereo sequence with black frames in the middle:
// the gap is reported (log, stats, absent from the trajectory), the VO re-initialises after
// it, and the poses after the recovery are accurate against the ground truth.
#include <gtest/gtest.h>

#include "pllvo/vo/run_sequence.h"
#include "synthetic_sequence.h"

namespace pllvo::vo {
namespace {

TEST(Recovery, BlackFramesAreAGapAndTrackingResumesAccurately) {
  const VoConfig config = testing::deterministic();
  const auto spec = testing::small_spec("easy_normal", 4.0, true);
  const size_t first_black = 35, last_black = 40;
  testing::BlackedOutSequence seq(io::open_sequence(testing::rendered(spec, "recovery")), first_black, last_black);
  const RunSummary s = run_sequence(seq, config, {});

  EXPECT_GE(s.resets, 1);
  ASSERT_EQ(s.lost.size(), 1u);
  EXPECT_LE(s.lost[0].first_frame, first_black);
  EXPECT_GE(s.lost[0].last_frame, last_black);
  EXPECT_LE(s.lost[0].last_frame, last_black + 1);  // back on the first frame after (stereo)
  ASSERT_EQ(s.stats["lost_intervals"].size(), 1u);
  EXPECT_EQ(s.stats["lost_intervals"][0]["first_frame"].get<size_t>(), s.lost[0].first_frame);
  EXPECT_EQ(s.tracked_frames, s.frames - (s.lost[0].last_frame - s.lost[0].first_frame + 1));

  // After the recovery: every frame tracked, and the new segment follows the true motion
  // (the segment starts at the last pose before the gap, so it is aligned on its own).
  io::Trajectory after;
  for (size_t i = 0; i < s.trajectory.size(); ++i)
    if (s.trajectory.stamps[i] > seq.timestamp(last_black)) after.push_back(s.trajectory.stamps[i], s.trajectory.poses[i]);
  EXPECT_EQ(after.size(), s.frames - 1 - s.lost[0].last_frame);
  const auto e = trajectory_error(after, *seq.ground_truth(), true);
  ASSERT_TRUE(e.has_value());
  std::printf("[ recovery ] lost frames %zu-%zu; after: %zu poses, SE3 ATE %.4f m = %.2f %% of %.2f m\n",
              s.lost[0].first_frame, s.lost[0].last_frame, after.size(), e->rmse_m, e->percent_of_path,
              e->path_length_m);
  EXPECT_GT(e->path_length_m, 0.3);
  // Half the EuRoC resolution (f = 229 px): 2-3 cm is this camera's accuracy on easy motion
  // (measured 2.1 cm / 2.4 % on the accuracy branch, 2.7 cm / 3.2 % after the session-2 merge).
  EXPECT_LT(e->rmse_m, 0.04);
  EXPECT_LT(e->percent_of_path, 4.5);
}

// The map restarted after the gap relocalises against the last keyframe before it
// (pose.relocalise_min_inliers), else starts at the last pose moved on by the last speed
// (pose.extrapolate_gap_max_s): either way the whole trajectory, both segments under one
// alignment, follows the truth better than a restart at the last pose, which leaves the
// motion of the gap out.
TEST(Recovery, TheTrajectoryStaysContinuousAcrossAShortGap) {
  const auto spec = testing::small_spec("easy_normal", 4.0, true);
  const size_t first_black = 35, last_black = 40;
  struct Outcome {
    double ate_m = 1e9;
    int relocalisations = 0;
  };
  auto run = [&](int relocalise_min_inliers, double extrapolate_gap_max_s) {
    VoConfig config = testing::deterministic();
    config.pose.relocalise_min_inliers = relocalise_min_inliers;
    config.pose.extrapolate_gap_max_s = extrapolate_gap_max_s;
    testing::BlackedOutSequence seq(io::open_sequence(testing::rendered(spec, "recovery")), first_black, last_black);
    const RunSummary s = run_sequence(seq, config, {});
    EXPECT_GE(s.resets, 1);
    Outcome o;
    if (const auto e = trajectory_error(s.trajectory, *seq.ground_truth(), true)) o.ate_m = e->rmse_m;
    o.relocalisations = s.stats["counts"].value("relocalisations", 0);
    return o;
  };
  const VoConfig defaults;
  const Outcome relocalised = run(defaults.pose.relocalise_min_inliers, defaults.pose.extrapolate_gap_max_s);
  const Outcome carried = run(0, defaults.pose.extrapolate_gap_max_s);
  const Outcome in_place = run(0, 0.0);
  std::printf("[ recovery ] whole trajectory SE3 ATE: %.4f m relocalised (%d), %.4f m carried on, %.4f m restarted "
              "at the last pose\n", relocalised.ate_m, relocalised.relocalisations, carried.ate_m, in_place.ate_m);
  EXPECT_EQ(relocalised.relocalisations, 1);
  EXPECT_EQ(carried.relocalisations, 0);
  EXPECT_LT(relocalised.ate_m, 0.6 * in_place.ate_m);  // measured 0.027 against 0.064 m
  EXPECT_LT(carried.ate_m, in_place.ate_m);
}

}  // namespace
}  // namespace pllvo::vo
