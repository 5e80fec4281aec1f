#include <gtest/gtest.h>

#include "pllvo/common/error.h"
#include "pllvo/features/lines/polygon_scene.h"

using namespace pllvo::lines;
using V = Eigen::Vector2d;

// The rendered edges sit where the truth says, to a small fraction of a pixel. Along a pixel
// row (column) crossing a steep (flat) edge, the normalised intensities are the shares of each
// pixel on the +x (+y) side of the edge, and their sum over a window locates the crossing
// exactly, whatever the slant: x_edge = x0 + 3.5 - sum over x0-3..x0+3.
TEST(PolygonScene, TruthMatchesTheRenderedEdges) {
  PolygonSceneConfig c;
  c.background_texture = 0.0;
  c.fine_texture = 0.0;
  c.noise_sigma = 0.0;
  c.num_ellipses = 0;
  const PolygonScene scene = render_polygon_scene(c);
  ASSERT_GE(scene.truth.size(), 30u);
  auto value = [&](int along, int across, int axis) {
    return static_cast<double>(axis == 0 ? scene.image.at<uchar>(across, along) : scene.image.at<uchar>(along, across));
  };
  int checked = 0;
  for (const auto& t : scene.truth) {
    const V d = t.direction();
    const int axis = std::abs(d.y()) > 0.8 ? 0 : (std::abs(d.x()) > 0.8 ? 1 : -1);  // 0: walk a row
    if (axis < 0 || t.length() < 40.0) continue;
    for (double s : {0.4, 0.5, 0.6}) {
      const int across = static_cast<int>(std::lround(t.at(s)[1 - axis]));  // row (or column) index
      // Where the true line crosses that row (column).
      const double crossing = t.start[axis] + (across - t.start[1 - axis]) * d[axis] / d[1 - axis];
      const int x0 = static_cast<int>(std::lround(crossing));
      const double plus = value(x0 + 5, across, axis), minus = value(x0 - 5, across, axis);
      ASSERT_GT(std::abs(plus - minus), 20.0);
      double sum = 0;
      for (int k = -3; k <= 3; ++k) sum += (value(x0 + k, across, axis) - minus) / (plus - minus);
      EXPECT_NEAR(x0 + 3.5 - sum, crossing, 0.1) << "edge " << t.id;
      ++checked;
    }
  }
  EXPECT_GE(checked, 10);
}

TEST(PolygonScene, SequencesMoveTheTruthRigidly) {
  const auto seq = polygon_tracking_sequence("normal", 3, 1.0, V(4, -2));
  ASSERT_EQ(seq.frames.size(), 3u);
  const auto& t0 = seq.frames[0].truth;
  const auto& t2 = seq.frames[2].truth;
  int compared = 0;
  for (const auto& a : t2) {
    for (const auto& b : t0) {
      if (a.id != b.id || std::abs(b.length() - a.length()) > 1e-6) continue;  // clipped edges differ
      EXPECT_LT((a.start - seq.motions[2] * b.start).norm(), 1e-9);
      ++compared;
    }
  }
  EXPECT_GT(compared, 20);
  EXPECT_THROW(polygon_suite("twilight", 1), pllvo::InputError);
}
