#include <gtest/gtest.h>

#include "pllvo/vo/map.h"

namespace pllvo::vo {
namespace {

TEST(MapData, FeatureViewGivesTheKeyframePoseAndPixelOrNothing) {
  MapData m;
  Keyframe kf;
  kf.T_world_cam.translation() = Eigen::Vector3d(1, 2, 3);
  kf.features.points = {{10.5f, 20.25f}, {30.f, 40.f}};
  const Id id = m.add_keyframe(kf);
  const auto view = m.feature_view({id, 1});
  ASSERT_TRUE(view.has_value());
  EXPECT_EQ(view->px, Eigen::Vector2d(30, 40));
  EXPECT_EQ(view->T_world_cam.translation(), Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(m.feature_view({id, 0})->px, Eigen::Vector2d(10.5, 20.25));
  EXPECT_FALSE(m.feature_view({id, 2}).has_value());   // past the last feature
  EXPECT_FALSE(m.feature_view({id, -1}).has_value());  // no feature
  EXPECT_FALSE(m.feature_view({id + 1, 0}).has_value());  // no such keyframe
  EXPECT_FALSE(m.feature_view({}).has_value());
}

}  // namespace
}  // namespace pllvo::vo
