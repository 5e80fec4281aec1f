// Metric stereo on real driving: KITTI 01 (far-field highway with a 98 deg turn) and KITTI 06
// (straight urban road), frames 0-50, with the default front end (SuperPoint + LightGlue) in
// the deterministic single-thread mode, against the sequences' ground truth (poses/*.txt).
//
// KITTI 01's rectified pair is about a pixel off in disparity: with it taken as given, the
// far points (4-8 px of disparity) made every step 1.19x too long (median) and the ATE 5.5 %.
// The window BA's estimate of the pair's offset (backend.bundle_adjustment.stereo_offset_sigma_px)
// is what these bounds check.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "pllvo/common/fixtures.h"
#include "pllvo/io/sequence.h"
#include "pllvo/vo/run_sequence.h"
#include "synthetic_sequence.h"

namespace pllvo::vo {
namespace {

using testing::default_single_thread;

/// Median over consecutive estimated frames of |estimated step| / |true step| (poses paired
/// by timestamp): 1 is the metric scale.
double median_step_ratio(const io::Trajectory& estimate, const io::Trajectory& truth) {
  auto truth_at = [&](double t) -> const Eigen::Isometry3d* {
    for (size_t i = 0; i < truth.size(); ++i)
      if (std::abs(truth.stamps[i] - t) < 1e-3) return &truth.poses[i];
    return nullptr;
  };
  std::vector<double> ratios;
  for (size_t k = 1; k < estimate.size(); ++k) {
    const auto* a = truth_at(estimate.stamps[k - 1]);
    const auto* b = truth_at(estimate.stamps[k]);
    if (!a || !b) continue;
    const double true_step = (b->translation() - a->translation()).norm();
    if (true_step < 0.1) continue;
    ratios.push_back((estimate.poses[k].translation() - estimate.poses[k - 1].translation()).norm() / true_step);
  }
  if (ratios.empty()) return NAN;
  std::nth_element(ratios.begin(), ratios.begin() + ratios.size() / 2, ratios.end());
  return ratios[ratios.size() / 2];
}

/// A whole 51-frame run must track every frame without a reset, with its median step ratio in
/// [min_ratio, max_ratio], its SE3 ATE under max_percent of the path as tracked and under
/// max_anchored_percent with every frame on its keyframe's final pose (keyframe_anchored_trajectory).
void expect_metric_run(const char* folder, double min_ratio, double max_ratio, double max_percent,
                       double max_anchored_percent) {
  const auto seq = io::open_sequence(shared_path(folder));
  const RunSummary s = run_sequence(*seq, default_single_thread(), RunOptions{});
  ASSERT_TRUE(seq->ground_truth().has_value());
  ASSERT_TRUE(s.error.has_value());
  ASSERT_TRUE(s.anchored_error.has_value());
  const double ratio = median_step_ratio(s.trajectory, *seq->ground_truth());
  std::printf("[ kitti stereo ] %s: %zu/%zu frames, %d resets, SE3 ATE %.3f m = %.2f %% of %.1f m, median step "
              "ratio %.3f; anchored %.3f m = %.2f %%\n",
              folder, s.tracked_frames, s.frames, s.resets, s.error->rmse_m, s.error->percent_of_path,
              s.error->path_length_m, ratio, s.anchored_error->rmse_m, s.anchored_error->percent_of_path);
  EXPECT_TRUE(s.stereo);
  EXPECT_EQ(s.tracked_frames, 51u);
  EXPECT_EQ(s.resets, 0);
  EXPECT_GT(ratio, min_ratio);
  EXPECT_LT(ratio, max_ratio);
  EXPECT_LT(s.error->percent_of_path, max_percent);
  EXPECT_LT(s.anchored_error->percent_of_path, max_anchored_percent);
}

TEST(KittiStereo, HighwayFarFieldKeepsTheMetricScale) {
  // Measured 1.51 % and 1.077 as tracked, 0.78 % anchored (5.5 % and 1.19 with the pair as given
  // and no offset estimate). ORB-SLAM3 on the same frames: 1.5-1.7 %, 1.05; its trajectory files
  // are anchored on keyframes the same way.
  expect_metric_run("data/kitti_01_stereo51/sequences/01", 0.95, 1.15, 4.5, 1.5);
}

TEST(KittiStereo, UrbanStraightStaysWithinATenthOfAPercent) {
  // Measured 0.04 % and 1.000, 0.05 % anchored (0.25 % with the pair as given; ORB-SLAM3 0.07 %).
  expect_metric_run("data/kitti_06_stereo51/sequences/06", 0.98, 1.02, 0.15, 0.15);
}

}  // namespace
}  // namespace pllvo::vo
