// RGB-D: the depth image as the metric source in place of a stereo pair (VoConfig::depth), on
// TUM fr3 office (real Kinect depth, 16 frames) and on synthetic sequences rendered with depth.
#include <gtest/gtest.h>

#include <cstdio>

#include "pllvo/common/error.h"
#include "pllvo/common/fixtures.h"
#include "pllvo/io/sequence.h"
#include "pllvo/vo/run_sequence.h"
#include "synthetic_sequence.h"

namespace pllvo::vo {
namespace {

using testing::default_single_thread;
using testing::deterministic;
using testing::WrappedSequence;

void print_run(const char* what, const RunSummary& s) {
  std::printf("[ rgbd ] %s: mode %s, %zu/%zu frames, %zu keyframes, %d resets", what, s.mode(), s.tracked_frames,
              s.frames, s.keyframes, s.resets);
  if (s.error)
    std::printf(", %s ATE %.4f m = %.2f %% of %.3f m over %zu poses", s.error->align.c_str(), s.error->rmse_m,
                s.error->percent_of_path, s.error->path_length_m, s.error->matched_poses);
  std::printf("\n");
}

/// Frame `i`'s depth with the pixels where `keep` is false set to 0 (no measurement).
class MaskedDepthSequence : public WrappedSequence {
 public:
  MaskedDepthSequence(std::unique_ptr<io::Sequence> inner, bool left_half_only)
      : WrappedSequence(std::move(inner)), left_half_only_(left_half_only) {}
  io::Frame frame(size_t i) const override {
    io::Frame f = WrappedSequence::frame(i);
    if (left_half_only_)
      f.depth(cv::Rect(0, 0, f.depth.cols / 2, f.depth.rows)).setTo(0);
    else
      f.depth.setTo(0);
    return f;
  }

 private:
  bool left_half_only_;
};

synth::SequenceSpec stereo_and_depth_spec() {
  synth::SequenceSpec spec = testing::small_spec("medium_normal", 4.0, true);
  spec.output.depth = true;
  return spec;
}

RunOptions rgbd_run() {
  RunOptions o;
  o.stereo = false;  // the sequence has a second camera too: use its depth images instead
  return o;
}

// `pllvo run` / `pllvo bench` --mono and --rgbd: which sensors a run uses.
TEST(RgbdOdometry, RunOptionsChooseTheSensorsAsTheCommandLineFlagsSay) {
  const auto tum = io::open_sequence(shared_path("data/tum_fr3_office_snippet"));
  const auto both = io::open_sequence(testing::rendered(stereo_and_depth_spec(), "rgbd_medium"));
  const auto kitti = io::open_sequence(shared_path("data/kitti_06_stereo51/sequences/06"));
  RunOptions o;
  o.choose_sensors(*both, false, false);
  EXPECT_TRUE(o.stereo && o.depth);  // the second camera first, else the depth images
  o.choose_sensors(*both, false, true);
  EXPECT_TRUE(!o.stereo && o.depth);
  o.choose_sensors(*both, true, false);
  EXPECT_TRUE(!o.stereo && !o.depth);
  o.choose_sensors(*tum, false, true);
  EXPECT_TRUE(!o.stereo && o.depth);
  try {
    o.choose_sensors(*kitti, false, true);
    ADD_FAILURE() << "--rgbd accepted on a sequence without depth";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("--rgbd"), std::string::npos) << what;
    EXPECT_NE(what.find("kitti_06_stereo51"), std::string::npos) << what;
  }
}

TEST(RgbdOdometry, TumOfficeTracksEveryFrameAtMetricScale) {
  const auto seq = io::open_sequence(shared_path("data/tum_fr3_office_snippet"));
  ASSERT_TRUE(seq->calibration().has_depth());
  const RunSummary s = run_sequence(*seq, default_single_thread(), RunOptions{});
  print_run("tum_fr3_office_snippet", s);
  EXPECT_TRUE(s.depth);
  EXPECT_FALSE(s.stereo);
  EXPECT_EQ(s.tracked_frames, 16u);  // the monocular run starts no map in these 16 frames
  EXPECT_EQ(s.resets, 0);
  ASSERT_TRUE(s.error.has_value());
  EXPECT_EQ(s.error->align, "se3");
  EXPECT_EQ(s.error->matched_poses, 14u);  // the ground truth covers 14 of the 16 frames
  EXPECT_LT(s.error->rmse_m, 0.005);       // measured 3.0 mm over a 19 mm path
  // Metric scale: the true path is 19 mm long, the estimate's largest distance from the start
  // measured 13.2 mm; a map at another scale would move by another amount.
  EXPECT_NEAR(s.max_displacement, 0.018, 0.006);
}

TEST(RgbdOdometry, SyntheticDepthKeepsTheStereoRunsAccuracy) {
  const auto seq = io::open_sequence(testing::rendered(stereo_and_depth_spec(), "rgbd_medium"));
  ASSERT_TRUE(seq->calibration().stereo());
  ASSERT_TRUE(seq->calibration().has_depth());
  const RunSummary stereo = run_sequence(*seq, deterministic(), RunOptions{});
  const RunSummary rgbd = run_sequence(*seq, deterministic(), rgbd_run());
  print_run("medium_normal 4 s stereo", stereo);
  print_run("medium_normal 4 s rgbd", rgbd);
  EXPECT_TRUE(stereo.stereo);
  EXPECT_TRUE(rgbd.depth);
  EXPECT_FALSE(rgbd.stereo);
  EXPECT_EQ(rgbd.tracked_frames, rgbd.frames);
  EXPECT_EQ(rgbd.resets, 0);
  ASSERT_TRUE(rgbd.error && stereo.error);
  EXPECT_EQ(rgbd.error->align, "se3");
  // Measured: RGB-D 1.30 %, stereo 2.70 % of the 2.78 m path (4 s of the preset, small images).
  EXPECT_LT(rgbd.error->percent_of_path, 2.0);
  EXPECT_LE(rgbd.error->percent_of_path, stereo.error->percent_of_path);
}

TEST(RgbdOdometry, HalfTheDepthMissingStillTracksAtMetricScale) {
  auto seq = std::make_unique<MaskedDepthSequence>(
      io::open_sequence(testing::rendered(stereo_and_depth_spec(), "rgbd_medium")), true);
  const RunSummary s = run_sequence(*seq, deterministic(), rgbd_run());
  print_run("medium_normal 4 s rgbd, left half without depth", s);
  EXPECT_EQ(s.tracked_frames, s.frames);
  ASSERT_TRUE(s.error.has_value());
  EXPECT_LT(s.error->percent_of_path, 2.5);  // measured 1.68 %
}

TEST(RgbdOdometry, NoMapStartsWithoutAnyDepth) {
  auto seq = std::make_unique<MaskedDepthSequence>(
      io::open_sequence(testing::rendered(stereo_and_depth_spec(), "rgbd_medium")), false);
  const RunSummary s = run_sequence(*seq, deterministic(), rgbd_run());
  print_run("medium_normal 4 s rgbd, no depth at all", s);
  EXPECT_TRUE(s.depth);
  EXPECT_EQ(s.tracked_frames, 0u);  // a one-frame start needs measured depth
  EXPECT_EQ(s.frames, seq->size());
}

}  // namespace
}  // namespace pllvo::vo
