#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "pllvo/features/lines/lines_config.h"

namespace fs = std::filesystem;
using namespace pllvo::lines;

namespace {
fs::path write_temp(const std::string& name, const std::string& text) {
  const auto p = fs::temp_directory_path() / ("pllvo_test_lines_" + name);
  std::ofstream(p) << text;
  return p;
}
}  // namespace

TEST(LinesConfig, DefaultFileMatchesTheDefaultsInCode) {
  const LinesConfig file = load_lines_config(fs::path(PLLVO_SOURCE_DIR) / "config/lines.yaml");
  const LinesConfig code;
  EXPECT_EQ(file.detector.min_length_px, code.detector.min_length_px);
  EXPECT_EQ(file.detector.min_gradient_ratio, code.detector.min_gradient_ratio);
  EXPECT_EQ(file.detector.support_max_angle_deg, code.detector.support_max_angle_deg);
  EXPECT_EQ(file.tracker.normalized_mean, code.tracker.normalized_mean);
  EXPECT_EQ(file.detector.edge_drawing.nfa_validation, code.detector.edge_drawing.nfa_validation);
  EXPECT_EQ(file.detector.edge_drawing.gradient_threshold, code.detector.edge_drawing.gradient_threshold);
  EXPECT_EQ(file.detector.prefilter.dark_level, code.detector.prefilter.dark_level);
  EXPECT_EQ(file.detector.prefilter.noise_row_step, code.detector.prefilter.noise_row_step);
  EXPECT_EQ(file.tracker.window_px, code.tracker.window_px);
  EXPECT_EQ(file.tracker.max_pyramid_level, code.tracker.max_pyramid_level);
  EXPECT_EQ(file.tracker.min_inlier_ratio, code.tracker.min_inlier_ratio);
  EXPECT_EQ(file.tracker.aperture_max_eigen_ratio, code.tracker.aperture_max_eigen_ratio);
  EXPECT_EQ(file.tracker.fit.huber_normal_px, code.tracker.fit.huber_normal_px);
  EXPECT_EQ(file.cross_constraint.max_overlap_angle_deg, code.cross_constraint.max_overlap_angle_deg);
  EXPECT_EQ(file.overlap_angles.histogram_bins, code.overlap_angles.histogram_bins);
  EXPECT_EQ(file.associator.max_descriptor_distance, code.associator.max_descriptor_distance);
  EXPECT_EQ(file.stereo.enabled, code.stereo.enabled);
  EXPECT_EQ(file.stereo.max_angle_deg, code.stereo.max_angle_deg);
  EXPECT_EQ(file.stereo.min_angle_from_horizontal_deg, code.stereo.min_angle_from_horizontal_deg);
  EXPECT_EQ(file.stereo.min_row_overlap, code.stereo.min_row_overlap);
  EXPECT_EQ(file.stereo.min_disparity_px, code.stereo.min_disparity_px);
  EXPECT_EQ(file.stereo.max_disparity_px, code.stereo.max_disparity_px);
  EXPECT_EQ(file.stereo.max_descriptor_distance, code.stereo.max_descriptor_distance);
  EXPECT_EQ(file.stereo.descriptor_ratio, code.stereo.descriptor_ratio);
  EXPECT_EQ(file.stereo.min_plane_angle_deg, code.stereo.min_plane_angle_deg);
}

TEST(LinesConfig, OverridesAndErrorsNameTheKey) {
  const auto ok = write_temp("ok.yaml", "detector:\n  min_length_px: 40\ntracker:\n  fit:\n    irls_iterations: 2\n");
  const LinesConfig c = load_lines_config(ok);
  EXPECT_EQ(c.detector.min_length_px, 40.0);
  EXPECT_EQ(c.tracker.fit.irls_iterations, 2);
  EXPECT_EQ(c.tracker.window_px, LineTrackerConfig{}.window_px);

  auto expect_key = [](const fs::path& file, const std::string& key) {
    try {
      load_lines_config(file);
      ADD_FAILURE() << "no error for " << key;
    } catch (const pllvo::InputError& e) {
      EXPECT_EQ(e.key(), key);
    }
  };
  expect_key(write_temp("typo.yaml", "tracker:\n  windw_px: 5\n"), "tracker.windw_px");
  expect_key(write_temp("type.yaml", "detector:\n  min_length_px: long\n"), "detector.min_length_px");
  expect_key(write_temp("range.yaml", "tracker:\n  min_inlier_ratio: 1.5\n"), "tracker.min_inlier_ratio");
  expect_key(write_temp("aperture.yaml", "tracker:\n  aperture_max_eigen_ratio: 1\n"),
             "tracker.aperture_max_eigen_ratio");
  expect_key(write_temp("op.yaml", "detector:\n  edge_drawing:\n    gradient_operator: canny\n"),
             "detector.edge_drawing.gradient_operator");
}
