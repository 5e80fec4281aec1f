#include <cmath>

#include <gtest/gtest.h>

#include "pllvo/vo/keyframe_policy.h"

namespace pllvo::vo {
namespace {

constexpr double kDeg = M_PI / 180.0;

KeyframePolicyConfig defaults() {
  KeyframePolicyConfig c;
  c.min_tracked_points = 60;
  c.min_tracked_ratio = 0.5;
  c.max_interval_s = 1.0;
  c.min_interval_s = 0.25;
  c.line_angle_change = 0.4;
  c.line_angle_tolerance_deg = 3.0;
  c.line_min_angles = 4;
  return c;
}

FrameTrackingState frame(double t, int points, bool idle = false, const std::vector<double>* angles = nullptr) {
  FrameTrackingState s;
  s.timestamp = t;
  s.tracked_points = points;
  s.backend_idle = idle;
  s.line_angles = angles;
  return s;
}

TEST(KeyframePolicy, FirstFrameIsAnInitialisationKeyframe) {
  KeyframePolicy policy(defaults());
  EXPECT_EQ(policy.decide(frame(0.0, 500)), KeyframeReason::kInitialization);
}

TEST(KeyframePolicy, PointTriggerFiresBelowTheCount) {
  KeyframePolicy policy(defaults());
  policy.start_keyframe(10.0, 100);
  EXPECT_EQ(policy.decide(frame(10.1, 60)), KeyframeReason::kNone);
  EXPECT_EQ(policy.decide(frame(10.1, 59)), KeyframeReason::kFewPoints);
}

TEST(KeyframePolicy, PointTriggerFiresWhenTrackingQualityDrops) {
  KeyframePolicy policy(defaults());
  policy.start_keyframe(10.0, 400);
  EXPECT_EQ(policy.decide(frame(10.1, 200)), KeyframeReason::kNone);
  EXPECT_EQ(policy.decide(frame(10.1, 199)), KeyframeReason::kTrackingQuality);
  // Once the keyframe's own points arrive the ratio is measured against them.
  policy.set_reference_points(600);
  EXPECT_EQ(policy.decide(frame(10.1, 299)), KeyframeReason::kTrackingQuality);
  EXPECT_EQ(policy.decide(frame(10.1, 300)), KeyframeReason::kNone);
}

TEST(KeyframePolicy, TimeTriggerHasAMaximumAndAnIdleMinimum) {
  KeyframePolicy policy(defaults());
  policy.start_keyframe(10.0, 300);
  EXPECT_EQ(policy.decide(frame(10.9, 300, false)), KeyframeReason::kNone);
  EXPECT_EQ(policy.decide(frame(11.0, 300, false)), KeyframeReason::kMaxInterval);
  // An idle back end takes a keyframe after the minimum interval, a busy one does not.
  EXPECT_EQ(policy.decide(frame(10.2, 300, true)), KeyframeReason::kNone);
  EXPECT_EQ(policy.decide(frame(10.3, 300, true)), KeyframeReason::kIdleInterval);
  EXPECT_EQ(policy.decide(frame(10.3, 300, false)), KeyframeReason::kNone);
}

TEST(KeyframePolicy, LineTriggerFiresWhenTheOverlapAngleSetChanges) {
  KeyframePolicy policy(defaults());
  const std::vector<double> ref = {10 * kDeg, 30 * kDeg, 50 * kDeg, 70 * kDeg, 85 * kDeg};
  policy.start_keyframe(10.0, 300, ref);
  // Small perturbations (< 3 deg): the same set.
  const std::vector<double> same = {11 * kDeg, 29 * kDeg, 52 * kDeg, 70.5 * kDeg, 84 * kDeg};
  EXPECT_EQ(policy.decide(frame(10.1, 300, false, &same)), KeyframeReason::kNone);
  // Two of five replaced: change 0.4, not above the threshold.
  const std::vector<double> two = {10 * kDeg, 30 * kDeg, 50 * kDeg, 20 * kDeg, 40 * kDeg};
  EXPECT_EQ(policy.decide(frame(10.1, 300, false, &two)), KeyframeReason::kNone);
  // Three of five replaced: change 0.6.
  const std::vector<double> three = {10 * kDeg, 30 * kDeg, 60 * kDeg, 20 * kDeg, 40 * kDeg};
  EXPECT_EQ(policy.decide(frame(10.1, 300, false, &three)), KeyframeReason::kLineAngles);
}

TEST(KeyframePolicy, LineTriggerNeedsEnoughAngles) {
  KeyframePolicy policy(defaults());
  policy.start_keyframe(10.0, 300, {10 * kDeg, 20 * kDeg});
  const std::vector<double> other = {60 * kDeg, 80 * kDeg, 70 * kDeg};
  EXPECT_EQ(policy.decide(frame(10.1, 300, false, &other)), KeyframeReason::kNone);
}

TEST(KeyframePolicy, EachTriggerCanBeSwitchedOff) {
  auto c = defaults();
  c.use_point_trigger = false;
  c.use_time_trigger = false;
  c.use_line_trigger = false;
  KeyframePolicy policy(c);
  const std::vector<double> ref = {10 * kDeg, 30 * kDeg, 50 * kDeg, 70 * kDeg};
  const std::vector<double> other = {15 * kDeg, 35 * kDeg, 55 * kDeg, 75 * kDeg};
  policy.start_keyframe(10.0, 300, ref);
  EXPECT_EQ(policy.decide(frame(100.0, 1, true, &other)), KeyframeReason::kNone);
}

TEST(KeyframePolicy, PointTriggerTakesPrecedence) {
  KeyframePolicy policy(defaults());
  policy.start_keyframe(10.0, 300);
  EXPECT_EQ(policy.decide(frame(12.0, 10, true)), KeyframeReason::kFewPoints);
}

TEST(AngleSetChange, CountsUnmatchedAnglesOneToOne) {
  EXPECT_DOUBLE_EQ(angle_set_change({}, {}, 0.1), 0.0);
  EXPECT_DOUBLE_EQ(angle_set_change({1.0, 2.0}, {2.05, 1.02}, 0.1), 0.0);
  EXPECT_DOUBLE_EQ(angle_set_change({1.0, 2.0}, {3.0}, 0.1), 1.0);
  // One reference angle can pair with only one current angle.
  EXPECT_DOUBLE_EQ(angle_set_change({1.0}, {1.0, 1.01, 1.02, 1.03}, 0.1), 0.75);
  EXPECT_DOUBLE_EQ(angle_set_change({1.0, 1.1, 5.0, 6.0}, {1.05, 1.12}, 0.1), 0.5);
}

TEST(KeyframeReason, NamesAreStable) {
  EXPECT_EQ(to_string(KeyframeReason::kFewPoints), "few_points");
  EXPECT_EQ(to_string(KeyframeReason::kLineAngles), "line_angles");
  EXPECT_EQ(all_keyframe_reasons().size(), 6u);
}

}  // namespace
}  // namespace pllvo::vo
