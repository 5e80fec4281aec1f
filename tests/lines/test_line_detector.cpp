#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "pllvo/common/error.h"
#include "pllvo/common/fixtures.h"
#include "pllvo/features/lines/line_detector.h"
#include "pllvo/features/lines/line_evaluation.h"
#include "pllvo/features/lines/polygon_scene.h"

using namespace pllvo::lines;

namespace {
DetectorComparison compare(const std::string& lighting, int frames) {
  DetectionScoreConfig score;
  score.min_truth_length_px = LineDetectorConfig{}.min_length_px;
  return compare_detectors(polygon_suite(lighting, frames), {}, score);
}
}  // namespace

// Done-when criterion: precision >= 0.9 on the normal-light suite and above LSD's in the same
// run (LSD as it comes, and LSD with the same minimum length).
TEST(LineDetector, PrecisionOnNormalSuiteBeatsLsd) {
  const DetectorComparison c = compare("normal", 10);
  EXPECT_GE(c.ours.precision(), 0.9);
  EXPECT_GT(c.ours.precision(), c.lsd.precision());
  EXPECT_GT(c.ours.precision(), c.lsd_min_length.precision());
  EXPECT_GE(c.ours.recall(), 0.9);
  // Sub-pixel refit: closer to the true edges than EdgeDrawing's and LSD's own endpoints.
  EXPECT_LT(c.ours.mean_normal_error(), 0.12);
  EXPECT_LT(c.ours.mean_normal_error(), c.edlines.mean_normal_error());
  EXPECT_LT(c.ours.mean_normal_error(), c.lsd.mean_normal_error());
  EXPECT_LT(c.ours.median_endpoint_error(), c.edlines.median_endpoint_error());
}

// Dark frames: the prefilter keeps the recall where plain EdgeDrawing and LSD lose most edges.
TEST(LineDetector, DarkAndNoisySuites) {
  const DetectorComparison dark = compare("dark", 4);
  EXPECT_GE(dark.ours.precision(), 0.9);
  EXPECT_GE(dark.ours.recall(), 0.75);
  EXPECT_GT(dark.ours.recall(), 1.5 * dark.edlines.recall());
  EXPECT_GT(dark.ours.recall(), 3.0 * dark.lsd.recall());
  const DetectorComparison noisy = compare("noisy", 4);
  EXPECT_GE(noisy.ours.precision(), 0.9);
  EXPECT_GE(noisy.ours.recall(), 0.85);
}

TEST(LineDetector, RealFrames) {
  const auto euroc = cv::imread(
      pllvo::shared_path("data/euroc_V1_01_easy_micro/mav0/cam0/data/1403715274312143104.png").string(),
      cv::IMREAD_GRAYSCALE);
  LineDetector detector;
  const auto lines = detector.detect(euroc);
  EXPECT_GE(lines.size(), 100u);
  for (size_t i = 0; i < lines.size(); ++i) {
    EXPECT_GE(lines[i].length(), 25.0);
    EXPECT_EQ(lines[i].id, static_cast<int>(i));
    if (i > 0) EXPECT_LE(lines[i].length(), lines[i - 1].length());
  }
  EXPECT_EQ(detector.last_stats().prefilter.gain, 1.0);

  // A dark frame of the HDR event-camera sequence: stretched, and lines found where plain
  // EdgeDrawing finds few.
  const auto dark = cv::imread(pllvo::shared_path("data/ecd_slider_hdr_close_149/images/frame_00000030.png").string(),
                               cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(dark.empty());
  const auto found = detector.detect(dark);
  EXPECT_GT(detector.last_stats().prefilter.gain, 2.0);
  EXPECT_GE(found.size(), 5u);
  LineDetectorConfig no_prefilter;
  no_prefilter.prefilter.enabled = false;
  EXPECT_GT(found.size(), LineDetector(no_prefilter).detect(dark).size());
}

TEST(LineDetector, MaxLinesKeepsTheLongest) {
  const auto scene = polygon_suite("normal", 1).front();
  LineDetectorConfig c;
  const auto all = LineDetector(c).detect(scene.image);
  c.max_lines = 10;
  const auto top = LineDetector(c).detect(scene.image);
  ASSERT_EQ(top.size(), 10u);
  for (size_t i = 0; i < top.size(); ++i) EXPECT_DOUBLE_EQ(top[i].length(), all[i].length());
}

TEST(LineDetector, RejectsBadImages) {
  LineDetector detector;
  EXPECT_THROW(detector.detect(cv::Mat()), pllvo::InputError);
  EXPECT_THROW(detector.detect(cv::Mat(100, 100, CV_8UC3, cv::Scalar::all(0))), pllvo::InputError);
  EXPECT_THROW(detector.detect(cv::Mat(100, 100, CV_32F, cv::Scalar(0))), pllvo::InputError);
  EXPECT_TRUE(detector.detect(cv::Mat(100, 100, CV_8UC1, cv::Scalar(0))).empty());
}
