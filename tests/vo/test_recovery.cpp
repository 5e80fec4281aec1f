// Tracking loss and recovery on a synthetic stereo sequence with black frames in the middle:
// the gap is reported (log, stats, absent from the trajectory), the VO re-initialises after
// it, and the poses after the recovery are accurate against the ground truth.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>

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
  // (measured 2.1 cm / 2.4 % on the accuracy branch, 2.7 cm / 3.2 % after the branches were merged).
  EXPECT_LT(e->rmse_m, 0.04);
  EXPECT_LT(e->percent_of_path, 4.5);
}

// The map restarted after the gap relocalises against the last keyframe before it
// (pose.relocalise_min_inliers), else starts at the last pose moved on by the last speed
// (pose.extrapolate_gap_max_s): either way the whole trajectory, both segments under one
// alignment, follows the truth better than a restart at the last pose, which leaves the
// motion of the gap out. The speed is the mean over the last frames
// (pose.extrapolate_velocity_frames): the last step alone carried this gap 0.124 m off, worse
// than the restart in place (0.055 m), once the stereo front end dropped edge points.
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

// A stereo frame that loses its pose (here: frames dropped by the camera, a jump KLT cannot
// follow) restarts the map on itself, relocalised in the old map (pose.stereo_restart_at_once):
// no frame is lost, and the trajectory stays accurate. Without it the frame and the next ones
// coast on the few tracks left and are lost.
TEST(Recovery, AStereoFrameThatLosesItsPoseRelocalisesAtOnce) {
  const auto spec = testing::small_spec("easy_normal", 4.0, true);
  const size_t first = 35, dropped = 12;  // 0.6 s
  auto run = [&](bool at_once) {
    VoConfig config = testing::deterministic();
    config.pose.stereo_restart_at_once = at_once;
    // The two restart policies alone: the stereo offset estimate wanders by tenths of a pixel on
    // this short half-resolution render (0.0314 against 0.0242 m with it), which is not what
    // this test compares.
    config.backend.bundle_adjustment.stereo_offset_sigma_px = 0;
    testing::FrameDroppingSequence seq(io::open_sequence(testing::rendered(spec, "recovery")), first, dropped);
    return run_sequence(seq, config, {});
  };
  const RunSummary now = run(true), later = run(false);
  const int relocalised_now = now.stats["counts"].value("restarts_relocalised_at_once", 0);
  std::printf("[ recovery ] %zu frames dropped: at once %zu of %zu tracked (%d relocalised at once), ATE %.4f m; "
              "after %d lost frames %zu of %zu tracked, ATE %.4f m\n",
              dropped, now.tracked_frames, now.frames, relocalised_now, now.error ? now.error->rmse_m : -1.0,
              VoConfig().pose.lost_frames_before_reset, later.tracked_frames, later.frames,
              later.error ? later.error->rmse_m : -1.0);
  EXPECT_EQ(relocalised_now, 1);
  // The try that decides the restart and the restart's first keyframe share one relocalisation.
  EXPECT_EQ(now.stats["timing_ms"]["kf_relocalise"].value("count", 0), 1);
  EXPECT_EQ(now.resets, 1);
  EXPECT_EQ(now.tracked_frames, now.frames);
  EXPECT_TRUE(now.lost.empty());
  ASSERT_TRUE(now.error.has_value());
  EXPECT_LT(now.error->rmse_m, 0.04);  // the accuracy bound of the black-frame test above
  ASSERT_FALSE(later.lost.empty());
  EXPECT_EQ(later.lost[0].first_frame, first);
  // Measured 0.0148 m at once against 0.0210 m after the lost frames (12 dropped; at 8 KLT
  // follows the jump, at 20 both relocalise ~0.3 m off after a 1 s jump), with the calibrated
  // working view; 0.0225 against 0.0203 m with the "fit" view, which also tracks the
  // three frames the later restart loses. A wrong relocalisation is ~0.1 m off.
  ASSERT_TRUE(later.error.has_value());
  EXPECT_LT(now.error->rmse_m, 1.25 * later.error->rmse_m);
}

// Estimated over true path length between t0 and t1: the scale of a monocular map there.
double scale_between(const io::Trajectory& est, const io::Trajectory& truth, double t0, double t1) {
  auto true_position = [&](double t) {
    const auto it = std::lower_bound(truth.stamps.begin(), truth.stamps.end(), t);
    return truth.poses[std::min<size_t>(it - truth.stamps.begin(), truth.size() - 1)].translation();
  };
  double estimated = 0, real = 0;
  std::optional<size_t> last;
  for (size_t i = 0; i < est.size(); ++i) {
    if (est.stamps[i] < t0 || est.stamps[i] > t1) continue;
    if (last) {
      estimated += (est.poses[i].translation() - est.poses[*last].translation()).norm();
      real += (true_position(est.stamps[i]) - true_position(est.stamps[*last])).norm();
    }
    last = i;
  }
  return real > 0 ? estimated / real : 0.0;
}

// A monocular map cannot relocalise by stereo: after the gap its frames try to relocalise
// against the last keyframes before it (pose.mono_resume_max_s, pose.relocalise_keyframes); the
// map then resumes at its own scale, so the whole trajectory fits the truth under one Sim3,
// where a new two-view start would begin a second map at another, arbitrary scale.
TEST(Recovery, AMonocularMapResumesAtItsScaleAfterAShortGap) {
  // The preset starts from rest: the two-view start comes at frame ~49 (2.5 s).
  const auto spec = testing::small_spec("easy_normal", 6.0, false);
  const size_t first_black = 75, last_black = 80;
  struct Outcome {
    double ate_percent = 1e9;
    int relocalisations = 0, resumed = 0, resets = 0;
    size_t frames = 0, tracked_after = 0;
    double scale_change = 0;  // the map's scale in the second after the gap over that in the second before
  };
  auto run = [&](double mono_resume_max_s) {
    VoConfig config = testing::deterministic();
    config.pose.mono_resume_max_s = mono_resume_max_s;
    testing::BlackedOutSequence seq(io::open_sequence(testing::rendered(spec, "recovery_mono")), first_black,
                                    last_black);
    const RunSummary s = run_sequence(seq, config, {});
    Outcome o;
    if (s.error) o.ate_percent = s.error->percent_of_path;
    o.relocalisations = s.stats["counts"].value("relocalisations", 0);
    o.resumed = s.stats["keyframes_by_reason"]["relocalisation"].get<int>();
    o.resets = s.resets;
    o.frames = s.frames;
    for (size_t i = 0; i < s.trajectory.size(); ++i) o.tracked_after += s.trajectory.stamps[i] > seq.timestamp(last_black);
    const double t0 = seq.timestamp(first_black), t1 = seq.timestamp(last_black + 1);
    o.scale_change = scale_between(s.trajectory, *seq.ground_truth(), t1, t1 + 1.0) /
                     scale_between(s.trajectory, *seq.ground_truth(), t0 - 1.0, t0);
    return o;
  };
  const Outcome resumed = run(VoConfig().pose.mono_resume_max_s);
  const Outcome restarted = run(0.0);
  std::printf("[ recovery ] mono: scale after the gap over before %.3f resumed (%d relocalisations, %zu poses after "
              "the gap), %.3f with a new two-view start; whole trajectory Sim3 ATE %.2f %% against %.2f %%\n",
              resumed.scale_change, resumed.relocalisations, resumed.tracked_after, restarted.scale_change,
              resumed.ate_percent, restarted.ate_percent);
  EXPECT_EQ(resumed.resets, 1);
  EXPECT_EQ(resumed.relocalisations, 1);
  EXPECT_EQ(resumed.resumed, 1);
  EXPECT_EQ(restarted.resumed, 0);
  // Back on the first frame after the gap: every later frame has a pose.
  EXPECT_EQ(resumed.tracked_after, resumed.frames - 1 - last_black);
  // Measured 1.088. Monocular runs follow the CPU's SIMD paths in their last digits and then
  // diverge (docs/vo.md), hence the margin; a new map's scale is unrelated (1.739 here).
  EXPECT_NEAR(resumed.scale_change, 1.0, 0.2);
  EXPECT_GT(std::abs(std::log(restarted.scale_change)), std::abs(std::log(resumed.scale_change)));
  EXPECT_LT(resumed.ate_percent, restarted.ate_percent);
}

// One black frame (a flash, a dropped exposure) fails its pose; it is not the next frame's KLT
// reference (pose.keep_reference_over_failed_frames), so the next frame is followed from the
// last tracked one and the map goes on. Taken as the reference, it cut every track (KLT finds
// nothing on it) and the next frames failed too until the map restarted.
TEST(Recovery, OneBlackFrameIsSkippedAndTheMapGoesOn) {
  struct Case {
    const char* name;
    bool stereo;
    size_t black;  // after the monocular start (~frame 49) as well
  };
  for (const Case c : {Case{"stereo", true, 60}, Case{"mono", false, 75}}) {
    const auto spec = testing::small_spec("easy_normal", 5.0, c.stereo);
    auto run = [&](bool keep_reference) {
      VoConfig config = testing::deterministic();
      config.pose.keep_reference_over_failed_frames = keep_reference;
      testing::BlackedOutSequence seq(io::open_sequence(testing::rendered(spec, std::string("one_black_") + c.name)),
                                      c.black, c.black);
      return run_sequence(seq, config, {});
    };
    const RunSummary kept = run(true), cut = run(false);
    std::printf("[ recovery ] %s, one black frame: reference kept %zu of %zu frames tracked, %d resets; taken as the "
                "reference %zu, %d resets; ATE %.2f %% against %.2f %%\n",
                c.name, kept.tracked_frames, kept.frames, kept.resets, cut.tracked_frames, cut.resets,
                kept.error ? kept.error->percent_of_path : -1.0, cut.error ? cut.error->percent_of_path : -1.0);
    EXPECT_EQ(kept.resets, 0) << c.name;
    ASSERT_EQ(kept.lost.size(), 1u) << c.name;
    EXPECT_EQ(kept.lost[0].first_frame, c.black) << c.name;
    EXPECT_EQ(kept.lost[0].last_frame, c.black) << c.name;
    EXPECT_EQ(testing::stats_count(kept.stats, "failed_frames_not_reference"), 1) << c.name;
    EXPECT_GE(cut.resets, 1) << c.name;
    ASSERT_TRUE(kept.error.has_value());
    ASSERT_TRUE(cut.error.has_value());
    // Measured (ORB, 376 x 240): stereo 1.54 % against 3.19 % after the restart; mono 7.14 %
    // against 7.29 % (a five-second flight whose map starts at frame ~49: short and coarse).
    if (c.stereo) EXPECT_LT(kept.error->percent_of_path, 0.75 * cut.error->percent_of_path) << c.name;
    EXPECT_LT(kept.error->percent_of_path, c.stereo ? 2.5 : 10.0) << c.name;
  }
}

}  // namespace
}  // namespace pllvo::vo
