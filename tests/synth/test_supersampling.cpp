// Supersampling (sensor.supersample): a pixel is the mean of f x f samples spread over its
// area, so a geometric edge crossing a pixel gives a value between the two sides instead of
// one side's (stair steps and broken dashes on edges: corners no real camera sees).
#include <gtest/gtest.h>

#include <cmath>

#include "synth_fixtures.h"

using namespace pllvo::synth;
using namespace pllvo::synth::testing;

namespace {

/// The checker wall's left edge (x = -2, depth 2 m) seen from a camera placed so that the edge
/// crosses the ideal image at column `c0 + offset` (c0 an integer column near the centre).
struct EdgeView {
  Scene scene = checker_scene(1.0);  // 1 m squares: the wall is uniform near its edge
  RadianceState radiance = bake_radiance(scene, 0, 1.0);
  int c0 = 0;
  Eigen::Isometry3d T_cam_world;

  EdgeView(const IdealView& view, double offset) {
    c0 = static_cast<int>(std::lround(view.cx));
    // Column of the edge: cx + fx * (x_edge - x_cam) / depth.
    const double x_cam = -2.0 - (c0 + offset - view.cx) * 2.0 / view.fx;
    T_cam_world = camera_facing_wall(x_cam).inverse();
  }
};

TEST(SynthSupersampling, AnEdgeThroughAPixelGivesItsSampleCoverage) {
  Generator gen(quiet_spec());
  const IdealView& view = gen.lens().ideal_view();
  // The edge at c0 + 0.1: pixel c0's centre lies outside the wall, one of its two sample
  // columns (c0 - 0.25, c0 + 0.25) inside.
  const EdgeView edge(view, 0.1);
  Rasterizer one(view, 0.05, true, 1), two(view, 0.05, true, 2), four(view, 0.05, true, 4);
  for (Rasterizer* r : {&one, &two, &four}) r->render(edge.scene, edge.radiance, edge.T_cam_world, 1.0f);

  const int y = static_cast<int>(std::lround(view.cy));
  const float wall = one.radiance().at<float>(y, edge.c0 + 2);
  ASSERT_GT(wall, 0.0f);
  EXPECT_NEAR(two.radiance().at<float>(y, edge.c0 + 2), wall, 0.02 * wall);
  EXPECT_EQ(one.radiance().at<float>(y, edge.c0 - 2), 0.0f);
  EXPECT_EQ(two.radiance().at<float>(y, edge.c0 - 2), 0.0f);
  // One sample at the centre: all or nothing. f x f samples: the share of them on the wall.
  EXPECT_EQ(one.radiance().at<float>(y, edge.c0), 0.0f);
  EXPECT_NEAR(two.radiance().at<float>(y, edge.c0), 0.5f * wall, 0.02 * wall);
  EXPECT_NEAR(four.radiance().at<float>(y, edge.c0), 0.5f * wall, 0.02 * wall);
  // Depth and quad id of a mixed pixel: the nearest sample's (the wall, 2 m away).
  EXPECT_EQ(one.inverse_depth().at<float>(y, edge.c0), 0.0f);
  EXPECT_NEAR(two.inverse_depth().at<float>(y, edge.c0), 0.5f, 1e-4);
  EXPECT_EQ(one.quad_ids().at<int32_t>(y, edge.c0), -1);
  EXPECT_EQ(two.quad_ids().at<int32_t>(y, edge.c0), 0);

  // Moved to c0 + 0.3: at f = 2 both sample columns (c0 -/+ 0.25) lie off the wall, at f = 4
  // one of the four (c0 + 0.375) is on it.
  const EdgeView later(view, 0.3);
  two.render(later.scene, later.radiance, later.T_cam_world, 1.0f);
  four.render(later.scene, later.radiance, later.T_cam_world, 1.0f);
  EXPECT_EQ(two.radiance().at<float>(y, later.c0), 0.0f);
  EXPECT_NEAR(four.radiance().at<float>(y, later.c0), 0.25f * wall, 0.02 * wall);
}

TEST(SynthSupersampling, KeepsTheImageAndOnlySoftensItsEdges) {
  SequenceSpec spec = quiet_spec();
  spec.sensor.psf_sigma_px = 0;
  RenderOptions options;
  options.noise = false;
  Generator plain = static_room(spec);
  spec.sensor.supersample = 2;
  Generator smooth = static_room(spec);
  const cv::Mat a = plain.render(0, options).cameras[0].image, b = smooth.render(0, options).cameras[0].image;
  // Same exposure and scene: the mean grey level agrees; pixels differ only along edges.
  EXPECT_NEAR(cv::mean(b)[0], cv::mean(a)[0], 0.01 * cv::mean(a)[0]);
  cv::Mat diff;
  cv::absdiff(a, b, diff);
  const double changed = cv::countNonZero(diff > 8) / static_cast<double>(diff.total());
  EXPECT_GT(changed, 0.001);
  EXPECT_LT(changed, 0.08);
}

}  // namespace
