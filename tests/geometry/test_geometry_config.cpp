#include <gtest/gtest.h>

#include <fstream>

#include "pllvo/geometry/geometry_config.h"
#include "pllvo/geometry/normalised.h"

using namespace pllvo::geometry;
namespace fs = std::filesystem;

namespace {
fs::path write_temp(const std::string& name, const std::string& text) {
  const auto p = fs::temp_directory_path() / ("pllvo_test_geometry_" + name);
  std::ofstream(p) << text;
  return p;
}
}  // namespace

TEST(GeometryConfig, DefaultFileMatchesTheDefaultsInCode) {
  const auto c = GeometryConfig::load_file(fs::path(PLLVO_SOURCE_DIR) / "config/geometry.yaml");
  const GeometryConfig d;
  EXPECT_EQ(c.point_triangulation.min_parallax_deg, d.point_triangulation.min_parallax_deg);
  EXPECT_EQ(c.point_triangulation.max_reprojection_error_px, d.point_triangulation.max_reprojection_error_px);
  EXPECT_EQ(c.point_triangulation.min_depth, d.point_triangulation.min_depth);
  EXPECT_EQ(c.point_triangulation.max_depth, d.point_triangulation.max_depth);
  EXPECT_EQ(c.point_triangulation.refine_iterations, d.point_triangulation.refine_iterations);
  EXPECT_EQ(c.line_triangulation.min_plane_angle_deg, d.line_triangulation.min_plane_angle_deg);
  EXPECT_EQ(c.line_triangulation.min_depth, d.line_triangulation.min_depth);
  EXPECT_EQ(c.line_triangulation.max_depth, d.line_triangulation.max_depth);
  EXPECT_EQ(c.line_triangulation.min_segment_length, d.line_triangulation.min_segment_length);
  EXPECT_EQ(c.line_triangulation.endpoints, d.line_triangulation.endpoints);
  EXPECT_EQ(c.pnp.method, d.pnp.method);
  EXPECT_EQ(c.pnp.reprojection_threshold_px, d.pnp.reprojection_threshold_px);
  EXPECT_EQ(c.pnp.confidence, d.pnp.confidence);
  EXPECT_EQ(c.pnp.max_iterations, d.pnp.max_iterations);
  EXPECT_EQ(c.pnp.min_inliers, d.pnp.min_inliers);
  EXPECT_EQ(c.pnp.refine, d.pnp.refine);
  EXPECT_EQ(c.two_view.sigma_px, d.two_view.sigma_px);
  EXPECT_EQ(c.two_view.ransac_threshold_px, d.two_view.ransac_threshold_px);
  EXPECT_EQ(c.two_view.ransac_confidence, d.two_view.ransac_confidence);
  EXPECT_EQ(c.two_view.ransac_max_iterations, d.two_view.ransac_max_iterations);
  EXPECT_EQ(c.two_view.homography_ratio, d.two_view.homography_ratio);
  EXPECT_EQ(c.two_view.max_reprojection_error_px, d.two_view.max_reprojection_error_px);
  EXPECT_EQ(c.two_view.min_point_parallax_deg, d.two_view.min_point_parallax_deg);
  EXPECT_EQ(c.two_view.min_median_parallax_deg, d.two_view.min_median_parallax_deg);
  EXPECT_EQ(c.two_view.min_triangulated, d.two_view.min_triangulated);
  EXPECT_EQ(c.two_view.min_good_fraction, d.two_view.min_good_fraction);
  EXPECT_EQ(c.two_view.max_ambiguity, d.two_view.max_ambiguity);
  EXPECT_EQ(c.two_view.max_direction_sigma_deg, d.two_view.max_direction_sigma_deg);
  EXPECT_EQ(c.two_view.vanishing_sigma_deg, d.two_view.vanishing_sigma_deg);
  EXPECT_EQ(c.two_view.vanishing_gate_deg, d.two_view.vanishing_gate_deg);
  EXPECT_EQ(c.stereo.max_epipolar_error_px, d.stereo.max_epipolar_error_px);
  EXPECT_EQ(c.stereo.min_disparity_px, d.stereo.min_disparity_px);
  EXPECT_EQ(c.stereo.max_disparity_px, d.stereo.max_disparity_px);
  EXPECT_EQ(c.stereo.min_depth, d.stereo.min_depth);
  EXPECT_EQ(c.stereo.max_depth, d.stereo.max_depth);
}

TEST(GeometryConfig, OverridesAndErrorsNameTheKey) {
  const auto c = GeometryConfig::load_file(
      write_temp("ok.yaml", "pnp:\n  method: epnp\n  min_inliers: 30\nline_triangulation:\n  endpoints: union\n"
                            "two_view:\n  vanishing_sigma_deg: 0.5\n  vanishing_gate_deg: 3\n"));
  EXPECT_EQ(c.pnp.method, PnpMethod::kEpnp);
  EXPECT_EQ(c.pnp.min_inliers, 30);
  EXPECT_EQ(c.line_triangulation.endpoints, LineEndpointSource::kUnion);
  EXPECT_EQ(c.two_view.homography_ratio, 0.45);  // default kept
  EXPECT_EQ(c.two_view.vanishing_sigma_deg, 0.5);
  EXPECT_EQ(c.two_view.vanishing_gate_deg, 3.0);

  for (const auto& [text, key] : {std::pair{"pnp:\n  method: p4p\n", "pnp.method"},
                                  std::pair{"stereo:\n  min_disparity: 2\n", "stereo.min_disparity"},
                                  std::pair{"two_view:\n  sigma_px: abc\n", "two_view.sigma_px"},
                                  std::pair{"triangulation: {}\n", "triangulation"}}) {
    try {
      GeometryConfig::load_file(write_temp("bad.yaml", text));
      FAIL() << text;
    } catch (const pllvo::InputError& e) {
      EXPECT_EQ(e.key(), key);
    }
  }
}

TEST(Normalised, PixelsRoundTripThroughTheCameraModel) {
  const pllvo::camera::PinholeRadtan cam(752, 480, {458.654, 457.296, 367.215, 248.375},
                                         {-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05});
  EXPECT_NEAR(pixel_scale(cam), 457.975, 1e-9);
  const Eigen::Vector3d p(0.3, -0.2, 2.0);
  Eigen::Vector2d uv, xy;
  ASSERT_TRUE(cam.project(p, uv));
  ASSERT_TRUE(pixel_to_normalised(cam, uv, xy));
  EXPECT_LT((xy - p.head<2>() / p.z()).norm(), 1e-9);
  const auto many = pixels_to_normalised(cam, {uv});
  EXPECT_LT((many[0] - xy).norm(), 1e-15);
}
