#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include "pllvo/vo/projection_search.h"

namespace pllvo::vo {
namespace {

// A 640 x 480 camera; an old keyframe at the origin sees points 4 m ahead; the new keyframe is
// 10 cm to the right (the points appear 10 px further left: f = 400).
Pinhole camera() {
  Pinhole c;
  c.fx = c.fy = 400;
  c.cx = 320;
  c.cy = 240;
  c.width = 640;
  c.height = 480;
  return c;
}

geometry::Pose camera_at(double x) {
  geometry::Pose T = geometry::Pose::Identity();
  T.translation() = Eigen::Vector3d(x, 0, 0);
  return T;
}

// Unit-norm float descriptors: `a` and `b` are 0.2 apart, `c` is far from both.
cv::Mat unit(int hot, float tilt = 0) {
  cv::Mat d = cv::Mat::zeros(1, 8, CV_32F);
  d.at<float>(hot) = 1;
  d.at<float>((hot + 1) % 8) = tilt;
  return d / cv::norm(d);
}

struct Scene {
  MapData map;
  Id keyframe = kNoId;
  std::vector<Id> points;
};

// Points at 4 m depth projecting to the given pixels of the keyframe at the origin.
Scene scene(const std::vector<Eigen::Vector2d>& pixels, const std::vector<cv::Mat>& descriptors) {
  Scene s;
  Keyframe kf;
  kf.T_world_cam = camera_at(0);
  for (size_t i = 0; i < pixels.size(); ++i) {
    kf.features.points.emplace_back(static_cast<float>(pixels[i].x()), static_cast<float>(pixels[i].y()));
    kf.features.descriptors.push_back(descriptors[i]);
  }
  kf.origins.resize(pixels.size());
  s.keyframe = s.map.add_keyframe(kf);
  const Pinhole cam = camera();
  for (size_t i = 0; i < pixels.size(); ++i) {
    const Id p = s.map.add_point(4.0 * Eigen::Vector3d(cam.normalised(pixels[i]).x(), cam.normalised(pixels[i]).y(), 1));
    s.map.observe_point(p, s.keyframe, static_cast<int>(i));
    s.points.push_back(p);
  }
  return s;
}

PointFeatures features(const std::vector<Eigen::Vector2d>& pixels, const std::vector<cv::Mat>& descriptors) {
  PointFeatures f;
  for (size_t i = 0; i < pixels.size(); ++i) {
    f.points.emplace_back(static_cast<float>(pixels[i].x()), static_cast<float>(pixels[i].y()));
    f.descriptors.push_back(descriptors[i]);
  }
  return f;
}

TEST(ProjectionSearch, ReattachesAPointWhereItProjectsWithItsDescriptor) {
  Scene s = scene({{300, 200}, {400, 300}}, {unit(0), unit(3)});
  // Seen from 10 cm right, the points are at (290, 200) and (390, 300). Feature 0 sits 2 px
  // from the first with a close descriptor; feature 1 sits 2 px from the second with a far one;
  // feature 2 has the first point's descriptor but lies 30 px from any projection.
  const PointFeatures f = features({{292, 200}, {390, 302}, {320, 200}}, {unit(0, 0.1f), unit(6), unit(0)});
  const auto found = search_by_projection(s.map, {s.keyframe}, camera(), camera_at(0.1), f,
                                          std::vector<Id>(3, kNoId), ProjectionSearchConfig{});
  ASSERT_EQ(found.size(), 3u);
  EXPECT_EQ(found[0], s.points[0]);
  EXPECT_EQ(found[1], kNoId);  // descriptor distance sqrt(2) > 0.7
  EXPECT_EQ(found[2], kNoId);  // outside the 5 px radius
}

TEST(ProjectionSearch, LeavesPointsAndFeaturesThatAreAlreadyAssociated) {
  Scene s = scene({{300, 200}, {400, 300}}, {unit(0), unit(3)});
  const PointFeatures f = features({{290, 200}, {390, 300}}, {unit(0), unit(3)});
  // Feature 0 already has a point (another one); point 1 is already taken by a track.
  const std::vector<Id> ids = {s.points[1] + 100, s.points[1]};
  const auto found = search_by_projection(s.map, {s.keyframe}, camera(), camera_at(0.1), f, ids, ProjectionSearchConfig{});
  EXPECT_EQ(found[0], kNoId);
  EXPECT_EQ(found[1], kNoId);
}

TEST(ProjectionSearch, AmbiguousNeighboursFailTheRatioTest) {
  Scene s = scene({{300, 200}}, {unit(0)});
  // Two features within the radius, 0.10 and 0.105 from the point's descriptor: ambiguous.
  const PointFeatures f = features({{289, 200}, {291, 201}}, {unit(0, 0.1f), unit(0, 0.105f)});
  const std::vector<Id> none(2, kNoId);
  EXPECT_EQ(search_by_projection(s.map, {s.keyframe}, camera(), camera_at(0.1), f, none, ProjectionSearchConfig{}),
            none);
  ProjectionSearchConfig loose;
  loose.ratio = 1.0;  // without the ratio test the nearer descriptor wins
  const auto found = search_by_projection(s.map, {s.keyframe}, camera(), camera_at(0.1), f, none, loose);
  EXPECT_EQ(found[0], s.points[0]);
  EXPECT_EQ(found[1], kNoId);
}

TEST(ProjectionSearch, OnePointPerFeatureTheNearestDescriptorWins) {
  // Two points project 2 px apart onto one feature; the one with the closer descriptor gets it.
  Scene s = scene({{300, 200}, {302, 200}}, {unit(0, 0.3f), unit(0, 0.05f)});
  const PointFeatures f = features({{291, 200}}, {unit(0)});
  const auto found = search_by_projection(s.map, {s.keyframe}, camera(), camera_at(0.1), f, {kNoId},
                                          ProjectionSearchConfig{});
  EXPECT_EQ(found[0], s.points[1]);
}

TEST(ProjectionSearch, SkipsPointsBehindOrOutsideTheCameraAndOtherKeyframes) {
  Scene s = scene({{300, 200}}, {unit(0)});
  const PointFeatures f = features({{290, 200}}, {unit(0)});
  const std::vector<Id> none(1, kNoId);
  geometry::Pose turned = camera_at(0.1);
  turned.linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitY()).toRotationMatrix();
  EXPECT_EQ(search_by_projection(s.map, {s.keyframe}, camera(), turned, f, none, {}), none);
  EXPECT_EQ(search_by_projection(s.map, {s.keyframe}, camera(), camera_at(5.0), f, none, {}), none);
  EXPECT_EQ(search_by_projection(s.map, {s.keyframe + 1}, camera(), camera_at(0.1), f, none, {}), none);
  ProjectionSearchConfig off;
  off.enabled = false;
  EXPECT_EQ(search_by_projection(s.map, {s.keyframe}, camera(), camera_at(0.1), f, none, off), none);
  EXPECT_EQ(search_by_projection(s.map, {s.keyframe}, camera(), camera_at(0.1), f, none, {})[0], s.points[0]);
}

TEST(ProjectionSearch, BinaryDescriptorsUseTheHammingDistance) {
  cv::Mat a = cv::Mat::zeros(1, 32, CV_8U), near = a.clone(), far = a.clone();
  near.at<unsigned char>(0) = 0x0F;        // 4 bits off
  far.colRange(0, 8).setTo(cv::Scalar(0xFF));  // 64 bits off
  Scene s = scene({{300, 200}, {400, 300}}, {a, a});
  const PointFeatures f = features({{290, 200}, {390, 300}}, {near, far});
  const auto found = search_by_projection(s.map, {s.keyframe}, camera(), camera_at(0.1), f,
                                          std::vector<Id>(2, kNoId), ProjectionSearchConfig{});
  EXPECT_EQ(found[0], s.points[0]);
  EXPECT_EQ(found[1], kNoId);  // 64 > 50
}

}  // namespace
}  // namespace pllvo::vo
