// The adaptive SuperPoint threshold: the rule on hand-made candidates, then Magic Leap's
// weights on synthetic low-light frames (the shared images darkened, with sensor noise).
#include <gtest/gtest.h>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "nn_test_util.h"
#include "pllvo/nn/adaptive_threshold.h"
#include "pllvo/nn/mnn_matcher.h"
#include "pllvo/nn/superpoint.h"

namespace pllvo::nn {
namespace {

// Candidates on a 80 x 60 map, one grid cell = 10 x 10 px with an 8 x 6 grid.
KeypointCandidates make_candidates(const std::vector<std::tuple<int, int, float>>& points) {
  KeypointCandidates c;
  c.width = 80;
  c.height = 60;
  for (const auto& [x, y, s] : points) {
    c.x.push_back(x);
    c.y.push_back(y);
    c.score.push_back(s);
  }
  return c;
}

TEST(AdaptiveThreshold, CountRuleKeepsTheTargetNumberOfStrongestPoints) {
  std::vector<std::tuple<int, int, float>> points;
  for (int i = 0; i < 48; ++i) points.emplace_back(10 * (i % 8) + 5, 10 * (i / 8) + 5, 0.01f * (i + 1));  // one per cell
  AdaptiveThresholdConfig config;
  config.target_keypoints = 10;
  config.min_occupancy = 0.0f;
  config.max_threshold = 1.0f;
  ThresholdDecision d;
  const auto selected = AdaptiveThreshold(config).select(make_candidates(points), &d);
  EXPECT_EQ(d.selected, 10);
  EXPECT_FLOAT_EQ(d.count_threshold, 0.38f);  // the 11th best of 0.01 .. 0.48
  EXPECT_FLOAT_EQ(d.threshold, 0.38f);
  config.max_threshold = 0.2f;  // the cap wins: every point above 0.2
  AdaptiveThreshold(config).select(make_candidates(points), &d);
  EXPECT_EQ(d.selected, 28);
}

TEST(AdaptiveThreshold, CoverageRuleLowersTheThresholdWhenStrongPointsCluster) {
  // 40 strong points in the top-left cell, one weak point in each of the other 47 cells.
  std::vector<std::tuple<int, int, float>> points;
  for (int i = 0; i < 40; ++i) points.emplace_back(i % 8, i / 8, 0.04f + 0.0001f * i);
  for (int cell = 1; cell < 48; ++cell) points.emplace_back(10 * (cell % 8) + 5, 10 * (cell / 8) + 5, 0.002f + 0.0001f * cell);
  AdaptiveThresholdConfig config;
  config.target_keypoints = 20;
  config.min_occupancy = 0.5f;
  const auto candidates = make_candidates(points);
  ThresholdDecision d;
  AdaptiveThreshold(config).select(candidates, &d);
  EXPECT_EQ(d.textured_cells, 48);
  EXPECT_GT(d.count_threshold, 0.04f);      // counting alone keeps 20 points in one cell
  EXPECT_LT(d.coverage_threshold, 0.0047f);  // coverage needs the best 24 cells
  EXPECT_GE(d.occupancy, 0.5f);
  EXPECT_EQ(d.selected, 40 + 23);
  config.min_occupancy = 0.0f;
  AdaptiveThreshold(config).select(candidates, &d);
  EXPECT_EQ(d.selected, 20);
  EXPECT_LT(d.occupancy, 0.05f);
}

TEST(AdaptiveThreshold, MatchingFeedbackMovesTheTarget) {
  AdaptiveThreshold at;
  EXPECT_EQ(at.target(), 500);
  at.report_matches(40, 500);  // poor
  EXPECT_EQ(at.target(), 625);
  for (int i = 0; i < 10; ++i) at.report_matches(10, 500);
  EXPECT_EQ(at.target(), 1000);  // capped at max_gain
  at.report_matches(150, 500);   // neither poor nor good: unchanged
  EXPECT_EQ(at.target(), 1000);
  for (int i = 0; i < 10; ++i) at.report_matches(400, 500);
  EXPECT_EQ(at.target(), 250);  // min_gain
}

// --- Real weights on synthetic low light --------------------------------------------------

const SuperPoint& magic_leap_superpoint() {
  static const SuperPoint net(SafeTensors::load(shared_path("models/superpoint_v1.safetensors")), {});
  return net;
}

// Dark frame: intensities scaled by `gain`, Gaussian sensor noise, 8-bit quantisation.
cv::Mat darken(const cv::Mat& image, double gain, double noise_sigma) {
  cv::Mat f, noise(image.size(), CV_32F), out;
  image.convertTo(f, CV_32F, gain);
  cv::RNG rng(7);
  rng.fill(noise, cv::RNG::NORMAL, 0.0, noise_sigma);
  cv::Mat(f + noise).convertTo(out, CV_8U);  // rounds and saturates
  return out;
}

// Keypoints of `f` within 3 px of their mutual nearest neighbour in `ref` (same geometry).
int correct_matches(const Features& ref, const Features& f) {
  MnnConfig config;
  config.distance_threshold = 0;  // no descriptor threshold: judge by position
  const auto m = match_mutual_nearest(ref, f, config);
  int correct = 0;
  for (int k = 0; k < m.size(); ++k)
    correct += (ref.keypoints.row(m.pairs(k, 0)) - f.keypoints.row(m.pairs(k, 1))).norm() <= 3.0f;
  return correct;
}

struct Measured {
  int count;
  float occupancy;
  int correct;
};

Measured measure(const Features& reference, const Features& f, const KeypointCandidates& candidates,
                 const std::vector<std::int32_t>& selected) {
  const auto [occupancy, textured] = grid_occupancy(candidates, selected, 8, 6, 0.0005f);
  return {f.size(), occupancy, correct_matches(reference, f)};
}

TEST(AdaptiveThreshold, DarkFrameKeepsEnoughWellSpreadCorrectPoints) {
  const auto& net = magic_leap_superpoint();
  const cv::Mat bright = cv::imread(test::superpoint_vector("icl250_640x480.png").string(), cv::IMREAD_GRAYSCALE);
  const Features reference = net.detect(bright, 0.005f, -1);
  AdaptiveThreshold adaptive;
  std::printf("%-6s %-9s %6s %9s %8s %9s\n", "gain", "threshold", "points", "occupancy", "correct", "threshold");
  for (const double gain : {0.3, 0.15, 0.08}) {
    const cv::Mat dark = darken(bright, gain, 2.0);
    const auto dense = net.run_network(dark);
    const auto candidates = find_candidates(dense.scores, 4, 4);
    const auto fixed_sel = select_keypoints(candidates, 0.005f, -1);
    ThresholdDecision d;
    const auto adaptive_sel = adaptive.select(candidates, &d);
    const auto fixed = measure(reference, extract_features(dense, candidates, fixed_sel), candidates, fixed_sel);
    const auto adapt = measure(reference, extract_features(dense, candidates, adaptive_sel), candidates, adaptive_sel);
    std::printf("%-6.2f fixed     %6d %9.2f %8d %9.4f\n", gain, fixed.count, fixed.occupancy, fixed.correct, 0.005);
    std::printf("%-6.2f adaptive  %6d %9.2f %8d %9.4f\n", gain, adapt.count, adapt.occupancy, adapt.correct, d.threshold);
    // Enough points, spread over the textured cells, and more of them correct than the fixed threshold's.
    EXPECT_GE(adapt.count, std::min(400, static_cast<int>(candidates.size())));
    EXPECT_GE(adapt.occupancy, 0.7f);
    EXPECT_GE(adapt.occupancy, fixed.occupancy);
    EXPECT_GE(adapt.correct, fixed.correct);
    if (gain <= 0.08) {
      EXPECT_LT(fixed.count, 200);               // the fixed threshold starves...
      EXPECT_GE(adapt.count, 2 * fixed.count);   // ...the adaptive one does not
      EXPECT_GE(adapt.correct, fixed.correct + 30);
    }
  }
}

TEST(AdaptiveThreshold, RichFrameDoesNotFlood) {
  const auto& net = magic_leap_superpoint();
  const cv::Mat rich = cv::imread(test::superpoint_vector("sacre_coeur2_752x480.png").string(), cv::IMREAD_GRAYSCALE);
  const auto dense = net.run_network(rich);
  const auto candidates = find_candidates(dense.scores, 4, 4);
  const auto low_fixed = select_keypoints(candidates, 0.0005f, -1);
  ThresholdDecision d;
  AdaptiveThreshold adaptive;
  const auto selected = adaptive.select(candidates, &d);
  std::printf("rich frame: fixed 0.0005 keeps %zu, adaptive %d (threshold %.4f, occupancy %.2f)\n", low_fixed.size(),
              d.selected, d.threshold, d.occupancy);
  EXPECT_GT(low_fixed.size(), 1500u);
  EXPECT_GE(d.selected, 500);
  EXPECT_LE(d.selected, 1000);
  EXPECT_GT(d.threshold, 0.0005f);
  EXPECT_GE(d.occupancy, 0.7f);
  // Poor matching asks for more points on the same frame.
  adaptive.report_matches(30, d.selected);
  ThresholdDecision more;
  adaptive.select(candidates, &more);
  EXPECT_GT(more.selected, d.selected);
  EXPECT_LT(more.threshold, d.threshold);
}

}  // namespace
}  // namespace pllvo::nn
