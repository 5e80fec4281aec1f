// config/nn.yaml lists every key with the defaults in code; a typo is an error naming the key.
#include <gtest/gtest.h>

#include <fstream>

#include "pllvo/common/error.h"
#include "pllvo/nn/nn_config.h"

namespace pllvo::nn {
namespace {

TEST(NnConfig, DefaultFileEqualsDefaultsInCode) {
  const auto c = NnConfig::load(std::filesystem::path(PLLVO_SOURCE_DIR) / "config/nn.yaml");
  const NnConfig d;
  EXPECT_EQ(c.threads, d.threads);
  EXPECT_EQ(c.superpoint.nms_radius, d.superpoint.nms_radius);
  EXPECT_EQ(c.superpoint.detection_threshold, d.superpoint.detection_threshold);
  EXPECT_EQ(c.superpoint.remove_borders, d.superpoint.remove_borders);
  EXPECT_EQ(c.superpoint.max_keypoints, d.superpoint.max_keypoints);
  EXPECT_EQ(c.superpoint.downscale, d.superpoint.downscale);
  EXPECT_EQ(c.superpoint.conv_layout, d.superpoint.conv_layout);
  const auto& a = c.adaptive_threshold;
  const auto& b = d.adaptive_threshold;
  EXPECT_EQ(a.target_keypoints, b.target_keypoints);
  EXPECT_EQ(a.max_keypoints, b.max_keypoints);
  EXPECT_EQ(a.min_threshold, b.min_threshold);
  EXPECT_EQ(a.max_threshold, b.max_threshold);
  EXPECT_EQ(a.grid_cols, b.grid_cols);
  EXPECT_EQ(a.grid_rows, b.grid_rows);
  EXPECT_EQ(a.min_occupancy, b.min_occupancy);
  EXPECT_EQ(a.poor_matches, b.poor_matches);
  EXPECT_EQ(a.poor_ratio, b.poor_ratio);
  EXPECT_EQ(a.good_matches, b.good_matches);
  EXPECT_EQ(a.good_ratio, b.good_ratio);
  EXPECT_EQ(a.gain_step, b.gain_step);
  EXPECT_EQ(a.min_gain, b.min_gain);
  EXPECT_EQ(a.max_gain, b.max_gain);
  EXPECT_EQ(c.matcher.type, d.matcher.type);
  EXPECT_EQ(c.matcher.lightglue.filter_threshold, d.matcher.lightglue.filter_threshold);
  EXPECT_EQ(c.matcher.lightglue.depth_confidence, d.matcher.lightglue.depth_confidence);
  EXPECT_EQ(c.matcher.lightglue.width_confidence, d.matcher.lightglue.width_confidence);
  EXPECT_EQ(c.matcher.lightglue.pruning_keypoint_threshold, d.matcher.lightglue.pruning_keypoint_threshold);
  EXPECT_TRUE(c.matcher.lightglue.weight_overrides.empty());
  EXPECT_EQ(c.matcher.mnn.mutual, d.matcher.mnn.mutual);
  EXPECT_EQ(c.matcher.mnn.ratio_threshold, d.matcher.mnn.ratio_threshold);
  EXPECT_EQ(c.matcher.mnn.distance_threshold, d.matcher.mnn.distance_threshold);
}

TEST(NnConfig, UnknownOrInvalidKeysNameTheKey) {
  const auto file = std::filesystem::temp_directory_path() / "pllvo_test_nn_config.yaml";
  const auto expect_key = [&](const std::string& yaml, const std::string& key) {
    std::ofstream(file) << yaml;
    try {
      NnConfig::load(file);
      ADD_FAILURE() << "no error for " << yaml;
    } catch (const InputError& e) {
      EXPECT_EQ(e.key(), key) << e.what();
    }
  };
  expect_key("superpoint:\n  nms_radious: 3\n", "superpoint.nms_radious");
  expect_key("matcher:\n  lightglue:\n    depth_confidence: 2\n", "matcher.lightglue.depth_confidence");
  expect_key("adaptive_threshold:\n  min_occupancy: 1.5\n", "adaptive_threshold.min_occupancy");
  expect_key("superpoint:\n  conv_layout: nhwc\n", "superpoint.conv_layout");
  std::filesystem::remove(file);
}

}  // namespace
}  // namespace pllvo::nn
