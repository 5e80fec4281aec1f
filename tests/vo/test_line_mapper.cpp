#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "pllvo/vo/line_mapper.h"

using namespace pllvo;
using V3 = Eigen::Vector3d;

namespace {
// A rectified stereo pair looking at dark and bright rectangles at known depths
// (fronto-parallel, so every edge of a rectangle lies at its depth).
struct Rectangle {
  double x0, y0, x1, y1, z;
  int grey;
};

constexpr double kBaseline = 0.11;

vo::Pinhole rectified_camera() {
  vo::Pinhole c;
  c.fx = c.fy = 460.0;
  c.cx = 376.0;
  c.cy = 240.0;
  c.width = 752;
  c.height = 480;
  return c;
}

cv::Mat render(const std::vector<Rectangle>& rects, double camera_x) {
  const vo::Pinhole c = rectified_camera();
  cv::Mat image(c.height, c.width, CV_8U, cv::Scalar(128));
  constexpr int kShift = 4;  // sub-pixel vertices
  for (const auto& r : rects) {  // far to near
    std::vector<cv::Point> poly;
    for (const auto& [x, y] : {std::pair{r.x0, r.y0}, {r.x1, r.y0}, {r.x1, r.y1}, {r.x0, r.y1}}) {
      Eigen::Vector2d px;
      c.project(V3(x - camera_x, y, r.z), px);
      poly.emplace_back(cvRound(px.x() * (1 << kShift)), cvRound(px.y() * (1 << kShift)));
    }
    cv::fillConvexPoly(image, poly, cv::Scalar(r.grey), cv::LINE_AA, kShift);
  }
  return image;
}

// Relative depth error of a 3-D line against the rectangle whose depth it is closest to (both ends).
double depth_error(const geometry::LineSegment3d& line, const std::vector<Rectangle>& rects) {
  double best = 1e9;
  for (const auto& r : rects)
    best = std::min(best, std::max(std::abs(line.start.z() - r.z), std::abs(line.end.z() - r.z)) / r.z);
  return best;
}
}  // namespace

TEST(LineMapper, StereoKeyframeTriangulatesLinesAtTheirMetricDepth) {
  // A slight tilt of every rectangle's x edges keeps the vertical edges off the image columns.
  const std::vector<Rectangle> rects = {{-1.6, -1.0, -0.4, 0.9, 4.5, 40},
                                        {0.3, -0.8, 1.5, 0.6, 3.0, 215},
                                        {-0.5, -0.3, 0.2, 0.7, 2.0, 60}};
  const cv::Mat left = render(rects, 0.0), right = render(rects, kBaseline);
  lines::LinesConfig config;
  config.stereo.enabled = true;
  vo::LineMapper mapper(config, geometry::LineTriangulationConfig{}, rectified_camera());
  vo::Map map;
  const auto plan = mapper.plan(left, geometry::Pose::Identity(), {}, nullptr, {}, map, right, kBaseline);
  ASSERT_GE(plan.segments.size(), 6u);
  // The vertical edges (two per rectangle, when not hidden) give stereo lines; horizontal ones cannot.
  EXPECT_GE(plan.from_stereo, 4);
  int checked = 0;
  for (const auto& t : plan.triangulated) {
    if (!t) continue;
    ++checked;
    EXPECT_LT(depth_error(*t, rects), 0.04) << "line at depth " << t->start.z() << " .. " << t->end.z();
  }
  EXPECT_EQ(checked, plan.from_stereo);
  // Without the right image, the first keyframe has no 3-D lines.
  const auto mono = mapper.plan(left, geometry::Pose::Identity(), {}, nullptr, {}, map);
  EXPECT_EQ(mono.from_stereo, 0);
}

TEST(LineMapper, MonocularLinesMeetTheKeyframesPlaneAngle) {
  // Side by side, each rectangle's vertical edges in full view from both keyframes. The second
  // keyframe is 0.2 m along x: at 2.5-4 m that baseline subtends 2.9-4.6 deg, which passes a
  // 2 deg plane angle (plain monocular keyframes', plain_scene.mono_line_min_plane_angle_deg)
  // and fails the monocular 5 deg.
  const std::vector<Rectangle> rects = {{-1.2, -0.9, -0.6, 0.8, 4.0, 40},
                                        {-0.3, -0.7, 0.25, 0.6, 3.2, 215},
                                        {0.45, -0.4, 0.85, 0.5, 2.5, 60}};
  constexpr double kStep = 0.2;
  const vo::Pinhole cam = rectified_camera();
  geometry::Pose second = geometry::Pose::Identity();
  second.translation() = V3(kStep, 0, 0);
  // The first keyframe's lines: the vertical edges' exact projections; their tracks end on the
  // second keyframe's projections, where detection finds the edges again.
  std::vector<vo::Segment2d> first_lines;
  std::vector<vo::TrackedLine> tracks;
  for (const auto& r : rects)
    for (const double x : {r.x0, r.x1}) {
      vo::Segment2d s0, s1;
      cam.project(V3(x, r.y0 + 0.1, r.z), s0.a);
      cam.project(V3(x, r.y1 - 0.1, r.z), s0.b);
      cam.project(V3(x - kStep, r.y0 + 0.1, r.z), s1.a);
      cam.project(V3(x - kStep, r.y1 - 0.1, r.z), s1.b);
      first_lines.push_back(s0);
      vo::TrackedLine t;
      t.segment = vo::to_line_segment(s1);
      tracks.push_back(t);
    }
  vo::Map map;
  vo::Id kf = vo::kNoId;
  map.write([&](vo::MapData& m) {
    vo::Keyframe k;
    k.lines = first_lines;
    kf = m.add_keyframe(std::move(k));
  });
  for (size_t i = 0; i < tracks.size(); ++i) tracks[i].origin = tracks[i].last = {kf, static_cast<int>(i)};

  geometry::LineTriangulationConfig mono;
  mono.min_plane_angle_deg = 5.0;
  vo::LineMapper mapper(lines::LinesConfig{}, mono, cam);
  const cv::Mat image = render(rects, kStep);
  auto count = [](const vo::LinePlan& p) {
    return std::count_if(p.triangulated.begin(), p.triangulated.end(), [](const auto& t) { return t.has_value(); });
  };
  const auto wide = mapper.plan(image, second, tracks, nullptr, {}, map);
  EXPECT_GE(wide.from_tracks, 5);
  EXPECT_EQ(count(wide), 0);
  const auto quiet = mapper.plan(image, second, tracks, nullptr, {}, map, {}, 0.0, 2.0);
  EXPECT_GE(count(quiet), 5);
  for (const auto& t : quiet.triangulated) {
    if (!t) continue;
    EXPECT_LT(depth_error(*t, rects), 0.05) << "line at depth " << t->start.z() << " .. " << t->end.z();
  }
}

TEST(LineMapper, DetectionsMadeByTheTrackerGiveTheSamePlan) {
  const std::vector<Rectangle> rects = {{-1.6, -1.0, -0.4, 0.9, 4.5, 40}, {0.3, -0.8, 1.5, 0.6, 3.0, 215}};
  const cv::Mat image = render(rects, 0.0);
  lines::LinesConfig config;
  vo::LineMapper mapper(config, geometry::LineTriangulationConfig{}, rectified_camera());
  vo::Map map;
  const auto raw = lines::LineDetector(config.detector).detect(image);
  // Handed-in detections still meet the cross constraint: a bundle of four segments crossing
  // at 4-12 deg in the empty top of the image must go, the rectangles' edges stay.
  std::vector<lines::LineSegment> cluttered = raw;
  for (int k = 0; k < 4; ++k) {
    const double a = 4.0 * k * M_PI / 180.0;
    const Eigen::Vector2d c(100, 40), d(70 * std::cos(a), 70 * std::sin(a));
    cluttered.emplace_back(c - d, c + d, 1000 + k);
  }
  const auto own = mapper.plan(image, geometry::Pose::Identity(), {}, nullptr, {}, map);
  ASSERT_GE(own.segments.size(), 6u);
  const std::vector<lines::LineSegment>* handed_in[] = {&raw, &cluttered};
  for (const auto* given : handed_in) {
    const auto plan = mapper.plan(image, geometry::Pose::Identity(), {}, nullptr, {}, map, {}, 0.0, std::nullopt, given);
    ASSERT_EQ(plan.segments.size(), own.segments.size()) << given->size() << " handed in";
    for (size_t i = 0; i < own.segments.size(); ++i) {
      EXPECT_EQ(plan.segments[i].start, own.segments[i].start);
      EXPECT_EQ(plan.segments[i].end, own.segments[i].end);
    }
  }
}
