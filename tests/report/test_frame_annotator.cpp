// Annotated frames: colours by state at the tracked positions; snapshot frames spread over a run.
#include <filesystem>

#include <gtest/gtest.h>

#include "pllvo/report/frame_annotator.h"
#include "pllvo/report/live_viewer.h"

namespace pllvo::report {
namespace {

namespace fs = std::filesystem;

vo::TrackingView view_with(size_t index, bool tracked) {
  vo::TrackingView v;
  v.frame_index = index;
  v.tracked = tracked;
  v.image = cv::Mat(120, 200, CV_8UC1, cv::Scalar(100));
  vo::TrackedPoint mapped, candidate;
  mapped.px = {50, 60};
  mapped.point = 7;
  candidate.px = {150, 60};
  v.points = {mapped, candidate};
  vo::TrackedLine line;
  line.segment = lines::LineSegment(Eigen::Vector2d(20, 100), Eigen::Vector2d(180, 100));
  line.line = 3;
  v.lines = {line};
  return v;
}

TEST(Annotate, DrawsEachStateInItsColourWhereItIs) {
  AnnotationStyle style;
  style.caption = false;
  const cv::Mat out = annotate(view_with(5, true), style);
  ASSERT_EQ(out.type(), CV_8UC3);
  ASSERT_EQ(out.size(), cv::Size(200, 120));
  EXPECT_EQ(out.at<cv::Vec3b>(60, 50), cv::Vec3b(60, 200, 60));    // map point: green
  EXPECT_EQ(out.at<cv::Vec3b>(60, 150), cv::Vec3b(0, 220, 255));   // candidate: yellow
  EXPECT_EQ(out.at<cv::Vec3b>(100, 100), cv::Vec3b(40, 40, 230)); // map line: red
  EXPECT_EQ(out.at<cv::Vec3b>(20, 100), cv::Vec3b(100, 100, 100)); // untouched grey elsewhere
}

TEST(FrameSnapshots, OneFrameNearEachTargetPreferringTrackedFrames) {
  const fs::path dir = fs::temp_directory_path() / "pllvo_report_snapshots";
  fs::remove_all(dir);
  FrameSnapshots snaps(dir, 0, 100, 4, 5);  // targets 12, 37, 62, 87
  for (size_t i = 0; i < 100; ++i) snaps(view_with(i, !(i >= 37 && i <= 39) && !(i >= 60 && i < 80)));
  ASSERT_EQ(snaps.written().size(), 4u);
  EXPECT_EQ(snaps.written()[0].filename(), "frame_12.png");
  EXPECT_EQ(snaps.written()[1].filename(), "frame_40.png");  // 37-39 not tracked
  EXPECT_EQ(snaps.written()[2].filename(), "frame_67.png");  // untracked until 80: patience 5 ends at 67
  EXPECT_EQ(snaps.written()[3].filename(), "frame_87.png");
  for (const auto& p : snaps.written()) EXPECT_TRUE(fs::exists(p));
}

TEST(FrameSnapshots, ZeroCountWritesNothing) {
  const fs::path dir = fs::temp_directory_path() / "pllvo_report_snapshots_none";
  fs::remove_all(dir);
  FrameSnapshots snaps(dir, 0, 100, 0);
  for (size_t i = 0; i < 100; ++i) snaps(view_with(i, true));
  EXPECT_TRUE(snaps.written().empty());
  EXPECT_FALSE(fs::exists(dir));
}

}  // namespace
}  // namespace pllvo::report
