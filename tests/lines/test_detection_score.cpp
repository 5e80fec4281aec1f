#include <gtest/gtest.h>

#include "pllvo/features/lines/detection_score.h"

using namespace pllvo::lines;
using V = Eigen::Vector2d;

TEST(DetectionScore, PrecisionRecallAndErrors) {
  const std::vector<LineSegment> truth = {LineSegment(V(0, 0), V(100, 0), 0), LineSegment(V(0, 50), V(0, 150), 1)};
  const std::vector<LineSegment> detected = {
      LineSegment(V(0.5, 0.3), V(99.0, -0.3)),  // whole edge 0: correct and complete
      LineSegment(V(0.4, 60), V(0.2, 90)),      // 30 px of edge 1: correct
      LineSegment(V(-0.3, 80), V(0.1, 110)),    // overlaps the previous on edge 1: correct
      LineSegment(V(10, 1), V(110, 1)),         // runs 10 px past the end of edge 0: wrong
      LineSegment(V(50, 50), V(80, 80)),        // nowhere: wrong
  };
  const DetectionScore s = score_line_detections(detected, truth);
  EXPECT_EQ(s.detections, 5);
  EXPECT_EQ(s.correct, 3);
  EXPECT_DOUBLE_EQ(s.precision(), 0.6);
  // Covered: [0.5, 99] of edge 0, and the union of [10, 40] and [30, 60] along edge 1 = 50.
  EXPECT_NEAR(s.recall(), (99.0 - 0.5 + 50.0) / 200.0, 1e-9);
  ASSERT_EQ(s.endpoint_errors.size(), 2u);
  EXPECT_NEAR(s.endpoint_errors[0], std::hypot(0.5, 0.3), 1e-12);
  EXPECT_NEAR(s.endpoint_errors[1], std::hypot(1.0, 0.3), 1e-12);
  ASSERT_EQ(s.normal_errors.size(), 6u);
  EXPECT_NEAR(s.normal_errors[0], 0.3, 1e-12);

  DetectionScore total = s;
  total.add(score_line_detections({}, truth));
  EXPECT_EQ(total.detections, 5);
  EXPECT_NEAR(total.recall(), s.recall() / 2, 1e-12);

  DetectionScoreConfig long_only;
  long_only.min_truth_length_px = 150;
  EXPECT_EQ(score_line_detections(detected, truth, long_only).truth_length, 0.0);
}

// A straight detection along a chain of collinear true segments (one 3-D edge cut into pieces,
// continued by another edge) is correct; recall counts only visible truth (contrast, edge length).
TEST(DetectionScore, ChainsOfTruthPiecesAndVisibility) {
  TruthFrame frame;
  frame.truth = {LineSegment(V(0, 0), V(50, 0), 0), LineSegment(V(50, 0), V(100, 0.5), 0),
                 LineSegment(V(100, 0.5), V(150, 1), 1), LineSegment(V(0, 40), V(100, 40), 2)};
  frame.contrast = {10, 10, 10, 3};
  const std::vector<LineSegment> detected = {
      LineSegment(V(1, 0), V(149, 1)),       // along the chain: correct
      LineSegment(V(0, 40.5), V(100, 40.5)),  // on a faint edge: correct (precision counts all truth)
      LineSegment(V(100, 0.5), V(170, 1.2)),  // runs 20 px past the end of the chain: wrong
      LineSegment(V(0, 20), V(60, 20)),       // nowhere: wrong
  };
  DetectionScoreConfig config;
  config.min_truth_contrast = 5;
  const DetectionScore s = score_line_detections(detected, frame, config);
  EXPECT_EQ(s.correct, 2);
  EXPECT_DOUBLE_EQ(s.precision(), 0.5);
  // Visible: the three chain pieces (~150 px); covered [1, 149] of them.
  EXPECT_NEAR(s.truth_length, 150.0, 0.01);
  EXPECT_NEAR(s.recall(), 148.0 / 150.0, 0.01);
  // Endpoint errors only for the detection covering one whole edge (the faint one).
  ASSERT_EQ(s.endpoint_errors.size(), 2u);
  EXPECT_NEAR(s.endpoint_errors[0], 0.5, 1e-9);
  const TruthMatch m = match_detection(detected[0], frame.truth, config);
  EXPECT_TRUE(m.correct);
  EXPECT_EQ(frame.truth[m.start_piece].id, 0);
  EXPECT_EQ(frame.truth[m.end_piece].id, 1);
  // Edge length counts per 3-D edge: with 60 px required, edge 1 (50 px) is not asked for.
  config.min_truth_length_px = 60;
  const DetectionScore long_only = score_line_detections(detected, frame, config);
  EXPECT_NEAR(long_only.truth_length, 100.0, 0.01);
  EXPECT_NEAR(long_only.recall(), 99.0 / 100.0, 0.01);
}
