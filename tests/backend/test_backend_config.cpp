#include <gtest/gtest.h>

#include <fstream>

#include "pllvo/backend/backend_config.h"

using namespace pllvo::backend;
namespace fs = std::filesystem;

namespace {
fs::path write_temp(const std::string& name, const std::string& text) {
  const auto p = fs::temp_directory_path() / ("pllvo_test_backend_" + name);
  std::ofstream(p) << text;
  return p;
}

void expect_same_loss(const RobustLoss& a, const RobustLoss& b) {
  EXPECT_EQ(a.type, b.type);
  EXPECT_EQ(a.scale_px, b.scale_px);
}
}  // namespace

TEST(BackendConfig, DefaultFileMatchesTheDefaultsInCode) {
  const auto c = BackendConfig::load_file(fs::path(PLLVO_SOURCE_DIR) / "config/backend.yaml");
  const BackendConfig d;
  const auto &p = c.pose_refiner, &pd = d.pose_refiner;
  expect_same_loss(p.point_loss, pd.point_loss);
  expect_same_loss(p.line_loss, pd.line_loss);
  EXPECT_EQ(p.line_weight, pd.line_weight);
  EXPECT_EQ(p.rounds, pd.rounds);
  EXPECT_EQ(p.iterations_per_round, pd.iterations_per_round);
  EXPECT_EQ(p.point_outlier_threshold_px, pd.point_outlier_threshold_px);
  EXPECT_EQ(p.line_outlier_threshold_px, pd.line_outlier_threshold_px);
  EXPECT_EQ(p.min_inliers, pd.min_inliers);
  EXPECT_EQ(p.use_motion_prior, pd.use_motion_prior);
  EXPECT_EQ(p.prior_sigma_position, pd.prior_sigma_position);
  EXPECT_EQ(p.prior_sigma_rotation_deg, pd.prior_sigma_rotation_deg);
  const auto &b = c.bundle_adjustment, &bd = d.bundle_adjustment;
  EXPECT_EQ(b.window_size, bd.window_size);
  EXPECT_EQ(b.num_fixed_oldest, bd.num_fixed_oldest);
  EXPECT_EQ(b.distance_gauge, bd.distance_gauge);
  EXPECT_EQ(b.min_point_observations, bd.min_point_observations);
  EXPECT_EQ(b.min_line_observations, bd.min_line_observations);
  expect_same_loss(b.point_loss, bd.point_loss);
  expect_same_loss(b.line_loss, bd.line_loss);
  EXPECT_EQ(b.line_weight, bd.line_weight);
  EXPECT_EQ(b.max_iterations, bd.max_iterations);
  EXPECT_EQ(b.second_pass, bd.second_pass);
  EXPECT_EQ(b.second_pass_iterations, bd.second_pass_iterations);
  EXPECT_EQ(b.point_outlier_threshold_px, bd.point_outlier_threshold_px);
  EXPECT_EQ(b.line_outlier_threshold_px, bd.line_outlier_threshold_px);
  EXPECT_EQ(b.function_tolerance, bd.function_tolerance);
  EXPECT_EQ(b.max_solver_time_s, bd.max_solver_time_s);
  EXPECT_EQ(b.num_threads, bd.num_threads);
  EXPECT_EQ(b.jacobians, bd.jacobians);
  EXPECT_EQ(b.linear_solver, bd.linear_solver);
}

TEST(BackendConfig, OverridesAndErrorsNameTheKey) {
  const auto c = BackendConfig::load_file(write_temp(
      "ok.yaml", "bundle_adjustment:\n  window_size: 7\n  point_loss: cauchy\n  jacobians: autodiff\n"
                 "  distance_gauge: true\n"
                 "pose_refiner:\n  use_motion_prior: false\n"));
  EXPECT_EQ(c.bundle_adjustment.window_size, 7);
  EXPECT_EQ(c.bundle_adjustment.point_loss.type, LossType::kCauchy);
  EXPECT_EQ(c.bundle_adjustment.jacobians, BaJacobians::kAutodiff);
  EXPECT_TRUE(c.bundle_adjustment.distance_gauge);
  EXPECT_FALSE(c.pose_refiner.use_motion_prior);
  EXPECT_EQ(c.bundle_adjustment.line_loss.type, LossType::kHuber);  // default kept

  for (const auto& [text, key] : {std::pair{"bundle_adjustment:\n  point_loss: tukey\n", "bundle_adjustment.point_loss"},
                                  std::pair{"bundle_adjustment:\n  window: 5\n", "bundle_adjustment.window"},
                                  std::pair{"bundle_adjustment:\n  window_size: 0\n", "bundle_adjustment.window_size"},
                                  std::pair{"pose_refiner:\n  line_loss_scale_px: -1\n", "pose_refiner.line_loss_scale_px"},
                                  std::pair{"pose_refiner:\n  rounds: two\n", "pose_refiner.rounds"},
                                  std::pair{"frontend: {}\n", "frontend"}}) {
    try {
      BackendConfig::load_file(write_temp("bad.yaml", text));
      FAIL() << text;
    } catch (const pllvo::InputError& e) {
      EXPECT_EQ(e.key(), key) << text;
    }
  }
}
