// Initialisation against synthetic ground truth: monocular two-view (relative rotation and
// translation direction of the two initial keyframes) and stereo (metric scale from the
// rectified pair). Sequences: the easy_normal preset at 376 x 240, rendered in the test; live
// starts (frames at their timestamps) on the KITTI drive (monocular) and TUM fr3 office (RGB-D).
#include <cmath>

#include <gtest/gtest.h>

#include "pllvo/common/fixtures.h"
#include "pllvo/io/trajectory.h"
#include "pllvo/synth/generator.h"
#include "pllvo/vo/run_sequence.h"
#include "synthetic_sequence.h"

namespace pllvo::vo {
namespace {

using testing::deterministic;

double angle_deg(const Eigen::Matrix3d& R) {
  return Eigen::AngleAxisd(R).angle() * 180.0 / M_PI;
}

double angle_between_deg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180.0 / M_PI;
}

TEST(Initialisation, MonocularTwoViewRecoversRotationAndTranslationDirection) {
  const auto spec = testing::small_spec("easy_normal", 3.0, false);
  const auto dir = testing::rendered(spec, "init_mono");
  const auto seq = io::open_sequence(dir);
  RunOptions options;
  // The preset's flight starts from rest: one second in, the camera moves at cruising speed.
  options.first_frame = 20;
  options.out_dir = std::filesystem::temp_directory_path() / ("pllvo_vo_test_init_mono_out_" + std::to_string(::getpid()));
  const RunSummary s = run_sequence(*seq, deterministic(), options);
  EXPECT_FALSE(s.stereo);
  EXPECT_EQ(s.resets, 0);
  EXPECT_EQ(s.tracked_frames, s.frames);  // frames before the two-view step get poses too
  ASSERT_GE(s.stats["keyframes_by_reason"]["initialization"].get<int>(), 2);

  // The first two keyframes are the two views of the initialisation.
  const io::Trajectory kf = io::read_tum(options.out_dir / "keyframes.tum");
  std::filesystem::remove_all(options.out_dir);
  ASSERT_GE(kf.size(), 2u);
  synth::Generator gen(spec);
  const double t0 = seq->timestamp(0);
  const Eigen::Isometry3d gt0 = gen.T_world_cam(0, kf.stamps[0] - t0), gt1 = gen.T_world_cam(0, kf.stamps[1] - t0);
  const Eigen::Isometry3d est01 = kf.poses[0].inverse() * kf.poses[1];
  const Eigen::Isometry3d gt01 = gt0.inverse() * gt1;
  const double rot_err = angle_deg(est01.linear().transpose() * gt01.linear());
  const double dir_err = angle_between_deg(est01.translation(), gt01.translation());
  std::printf("[ mono init ] views %.2f-%.2f s: true rotation %.2f deg, baseline %.3f m; error %.3f deg, "
              "direction %.2f deg; sim3 ATE %.2f %% of the path\n",
              kf.stamps[0] - t0, kf.stamps[1] - t0, angle_deg(gt01.linear()), gt01.translation().norm(), rot_err,
              dir_err, s.error ? s.error->percent_of_path : -1.0);
  EXPECT_GT(gt01.translation().norm(), 0.01);
  // Measured: 0.47 deg and 14.6 deg at this half resolution. The direction is
  // far from the two-view's accuracy on ideal points (< 1 deg, tests/geometry); the bounds
  // catch a wrong decomposition (tens of degrees) and keep what is reached now. See docs/vo.md.
  EXPECT_LT(rot_err, 1.0);
  EXPECT_LT(dir_err, 20.0);
  ASSERT_TRUE(s.error.has_value());
  // Sim3 ATE over the 3 s: 2.9 % on the accuracy branch alone, 5.5 % once merged with the front-end
  // and line-detector changes (initialisation 0.2 s earlier, 0.09 m baseline): the bound catches a
  // broken mono pipeline (tens of %), not the last percent (docs/vo.md).
  EXPECT_LT(s.error->percent_of_path, 8.0);
}

TEST(Initialisation, StereoStartsOnTheFirstFrameAtMetricScale) {
  const auto spec = testing::small_spec("easy_normal", 3.0, true);
  const auto dir = testing::rendered(spec, "init_stereo");
  const auto seq = io::open_sequence(dir);
  const RunSummary s = run_sequence(*seq, deterministic(), {});
  EXPECT_TRUE(s.stereo);
  EXPECT_EQ(s.resets, 0);
  EXPECT_EQ(s.tracked_frames, s.frames);  // initialised on the first frame
  EXPECT_EQ(s.stats["keyframes_by_reason"]["initialization"].get<int>(), 1);
  // On one thread every keyframe is back before the next frame.
  const auto& back = s.stats["per_frame"]["keyframe_return_frames"];
  EXPECT_GE(back["count"].get<int>(), 2);
  EXPECT_EQ(back["max"].get<double>(), 0.0);

  // Scale: the distance between the first and the last pose, estimated vs true. The pose is
  // in metres from the stereo baseline alone; no alignment involved.
  synth::Generator gen(spec);
  const double t0 = seq->timestamp(0);
  const size_t n = s.trajectory.size();
  ASSERT_EQ(n, s.frames);
  const double est = (s.trajectory.poses[n - 1].translation() - s.trajectory.poses[0].translation()).norm();
  const double truth = (gen.T_world_cam(0, s.trajectory.stamps[n - 1] - t0).translation() -
                        gen.T_world_cam(0, s.trajectory.stamps[0] - t0).translation()).norm();
  std::printf("[ stereo init ] first to last frame: %.4f m estimated, %.4f m true (ratio %.4f); SE3 ATE %.4f m = %.2f %%\n",
              est, truth, est / truth, s.error ? s.error->rmse_m : -1.0, s.error ? s.error->percent_of_path : -1.0);
  ASSERT_GT(truth, 0.3);
  // Measured 0.9475 on an AMD EPYC host and above 0.95 on CI's machine for the same
  // commit: the last percent moves with the CPU's SIMD paths (OpenCV's runtime dispatch: 0.9472
  // with its AVX2 and FMA3 paths disabled). A broken baseline or rectification is off by tens of %.
  EXPECT_NEAR(est / truth, 1.0, 0.07);
  ASSERT_TRUE(s.error.has_value());
  EXPECT_EQ(s.error->align, "se3");
  // Measured: 0.016 m = 2.2 % of 0.74 m at half the EuRoC resolution (f = 229 px);
  // 0.025 m = 3.4 % since the working view "fit" spans the whole distorted image with
  // f = 178 / 209 px at this resolution (docs/vo.md).
  EXPECT_LT(s.error->rmse_m, 0.032);
  EXPECT_LT(s.error->percent_of_path, 4.3);
}

/// The default pipeline on its threads, as `pllvo run` runs it.
VoConfig default_threaded() {
  VoConfig config = testing::default_single_thread();
  config.run.threaded = true;
  return config;
}

// A live monocular start runs its network steps (detection, the two-view start's keyframes) on
// the keyframe worker: the tracker takes the next frames meanwhile, and the map that comes back
// after its frame is brought up to the latest one through the frames' buffered pyramids. Offline
// input waits for each step, so that it applies at its own frame, as on one thread.
TEST(Initialisation, ALiveMonocularStartRunsBesideTheTrackerAndCatchesUp) {
  const auto seq = io::open_sequence(shared_path("data/kitti_04_mono51"));
  const VoConfig config = default_threaded();
  RunOptions options;
  options.max_frames = 30;
  options.stereo = false;
  const RunSummary offline = run_sequence(*seq, config, options);
  options.realtime = true;  // frames at their timestamps (10 Hz): the tracker never waits for the worker
  const RunSummary live = run_sequence(*seq, config, options);
  ASSERT_TRUE(live.live.has_value());
  const size_t dropped = live.live->dropped_frames.size();
  const auto late = [](const RunSummary& s) { return testing::stats_count(s.stats, "start_steps_applied_late"); };
  std::printf("[ live mono start ] offline: %zu of %zu frames tracked, %lld start steps; live: %zu tracked, %zu "
              "dropped, %lld start steps (%lld applied after their frame), Sim3 ATE %.2f %%\n",
              offline.tracked_frames, offline.frames, testing::stats_count(offline.stats, "start_steps"),
              live.tracked_frames, dropped, testing::stats_count(live.stats, "start_steps"), late(live),
              live.error ? live.error->percent_of_path : -1.0);
  EXPECT_EQ(offline.tracked_frames, 30u);
  EXPECT_GE(testing::stats_count(offline.stats, "start_steps"), 2);  // the reference's detection, the two-view start
  EXPECT_EQ(late(offline), 0);
  // Live, a step's outcome reaches the tracker on a later frame than its own: at least the
  // first detection's, which the tracker did not wait for.
  EXPECT_GE(late(live), 1);
  EXPECT_EQ(live.resets, 0);
  // The frames that passed while the start ran get their poses when it comes back: of the frames
  // the tracker took, all but at most 3 (where PnP on the new map fails) have one (measured: 30
  // of 30, none dropped, 0.3-0.5 %).
  EXPECT_GE(live.tracked_frames + dropped + 3, live.frames);
  EXPECT_GE(live.tracked_frames, 20u);
  ASSERT_TRUE(live.error.has_value());
  EXPECT_LT(live.error->percent_of_path, 2.0);
  // Keyframes after the start come back frames after their request (SuperPoint and LightGlue
  // at 1241 x 376 take longer than the 100 ms between frames): the summary says how many.
  const auto& rt = live.stats["realtime"];
  ASSERT_TRUE(rt["keyframe_return_frames_mean"].is_number()) << rt.dump();
  EXPECT_GE(rt["keyframe_return_frames_mean"].get<double>(), 1.0);
  EXPECT_GT(rt["keyframe_return_ms_mean"].get<double>(), 100.0);
}

// The same for an RGB-D start on TUM fr3 office (30 Hz): the frames that arrive while the first
// keyframe is made are tracked, not dropped, and get their poses when it comes back.
TEST(Initialisation, ALiveRgbdStartRunsBesideTheTrackerAndCatchesUp) {
  const auto seq = io::open_sequence(shared_path("data/tum_fr3_office_snippet"));
  const VoConfig config = default_threaded();
  RunOptions options;
  options.realtime = true;
  const RunSummary live = run_sequence(*seq, config, options);
  ASSERT_TRUE(live.depth);
  ASSERT_TRUE(live.live.has_value());
  const size_t dropped = live.live->dropped_frames.size();
  std::printf("[ live RGB-D start ] %zu of %zu frames tracked, %zu dropped, %lld start steps applied after their "
              "frame, SE3 ATE %.4f m\n",
              live.tracked_frames, live.frames, dropped, testing::stats_count(live.stats, "start_steps_applied_late"),
              live.error ? live.error->rmse_m : -1.0);
  EXPECT_GE(testing::stats_count(live.stats, "start_steps_applied_late"), 1);
  EXPECT_EQ(live.resets, 0);
  // Every frame the tracker took has a pose, also when the start comes back after the last frame
  // (measured: 16 of 16, none dropped; the start on the tracking thread dropped the 3-4 frames
  // that arrived during its 162 ms).
  EXPECT_EQ(live.tracked_frames + dropped, live.frames);
  ASSERT_TRUE(live.error.has_value());
  EXPECT_LT(live.error->rmse_m, 0.005);  // measured 1.8 mm; offline single thread 3.0 mm
}

}  // namespace
}  // namespace pllvo::vo
