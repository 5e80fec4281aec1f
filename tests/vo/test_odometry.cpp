// The pipeline end to end on the real fixtures, in the deterministic single-thread mode:
// stereo initialisation (EuRoC, camera at rest), monocular initialisation and tracking
// (KITTI drive), and a tracking loss with recovery (black frames inserted).
#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "pllvo/common/fixtures.h"
#include "pllvo/io/sequence.h"
#include "pllvo/vo/run_sequence.h"
#include "synthetic_sequence.h"

namespace pllvo::vo {
namespace {

using testing::BlackedOutSequence;
using testing::deterministic;

/// A sequence that leaves memory allocated behind every frame it reads, a different amount
/// each frame: the heap then places everything the pipeline allocates elsewhere.
class HeapChurningSequence : public testing::WrappedSequence {
 public:
  using WrappedSequence::WrappedSequence;
  io::Frame frame(size_t i) const override {
    for (size_t k = 0; k <= i % 5; ++k) kept_.emplace_back(new char[48 + 200 * ((i + 3 * k) % 9)]);
    return WrappedSequence::frame(i);
  }

 private:
  mutable std::vector<std::unique_ptr<char[]>> kept_;
};

TEST(Odometry, StereoInitialisesAtMetricScaleAndStaysStillOnEuroc) {
  const auto seq = io::open_sequence(shared_path("data/euroc_V1_01_easy_micro"));
  RunOptions options;
  options.max_frames = 40;
  const RunSummary s = run_sequence(*seq, deterministic(), options);
  EXPECT_TRUE(s.stereo);
  EXPECT_EQ(s.tracked_frames, 40u);  // initialised on the first frame
  EXPECT_EQ(s.stats["keyframes_by_reason"]["initialization"].get<int>(), 1);
  EXPECT_EQ(s.resets, 0);
  // The MAV is at rest (ground truth moves < 4 mm): the estimate must stay within 1 cm.
  EXPECT_LT(s.max_displacement, 0.01);
  ASSERT_TRUE(s.error.has_value());
  EXPECT_LT(s.error->rmse_m, 0.005);
}

TEST(Odometry, MonocularInitialisesAndFollowsTheKittiDrive) {
  const auto seq = io::open_sequence(shared_path("data/kitti_04_mono51"));
  RunOptions options;
  options.max_frames = 30;
  const RunSummary s = run_sequence(*seq, deterministic(), options);
  EXPECT_FALSE(s.stereo);
  EXPECT_EQ(s.tracked_frames, 30u);  // frames before the two-view initialisation get poses too
  EXPECT_EQ(s.resets, 0);
  EXPECT_GE(s.stats["keyframes_by_reason"]["initialization"].get<int>(), 2);
  ASSERT_TRUE(s.error.has_value());
  EXPECT_EQ(s.error->align, "sim3");
  EXPECT_GT(s.error->path_length_m, 30.0);
  EXPECT_LT(s.error->percent_of_path, 1.0) << "ATE " << s.error->rmse_m << " m";
}

TEST(Odometry, SingleThreadRunsRepeatWhateverElseUsesTheHeap) {
  // The single-thread mode is for tests and measurements: its result must not depend on what
  // else allocated memory before (a progress line printed on a timer, another reader). The
  // bundle adjustment once followed the heap's placement of its blocks (docs/vo.md).
  const auto path = shared_path("data/kitti_04_mono51");
  RunOptions options;
  options.max_frames = 30;
  const RunSummary plain = run_sequence(*io::open_sequence(path), deterministic(), options);
  const RunSummary churned = run_sequence(HeapChurningSequence(io::open_sequence(path)), deterministic(), options);
  ASSERT_EQ(plain.trajectory.size(), churned.trajectory.size());
  ASSERT_GE(plain.trajectory.size(), 20u);
  for (size_t i = 0; i < plain.trajectory.size(); ++i)
    EXPECT_TRUE(plain.trajectory.poses[i].matrix() == churned.trajectory.poses[i].matrix()) << "frame " << i;
}

TEST(Odometry, LosesTrackOnBlackFramesAndRecoversAfterThem) {
  BlackedOutSequence seq(io::open_sequence(shared_path("data/kitti_04_mono51")), 15, 18);
  RunOptions options;
  options.max_frames = 40;
  const RunSummary s = run_sequence(seq, deterministic(), options);
  EXPECT_GE(s.resets, 1);
  ASSERT_FALSE(s.lost.empty());
  // The black frames are not tracked, and the gap is reported.
  bool covered = false;
  for (const auto& l : s.lost) covered |= l.first_frame <= 15 && l.last_frame >= 18;
  EXPECT_TRUE(covered);
  // Tracking resumes after the black frames: the last frames have poses again.
  const double last_stamp = seq.timestamp(39);
  ASSERT_FALSE(s.trajectory.empty());
  EXPECT_DOUBLE_EQ(s.trajectory.stamps.back(), last_stamp);
  EXPECT_GE(s.tracked_frames, 30u);
  EXPECT_EQ(s.stats["lost_intervals"].size(), s.lost.size());
}

}  // namespace
}  // namespace pllvo::vo
