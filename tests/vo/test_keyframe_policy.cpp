#include <cmath>

#include <gtest/gtest.h>

#include "pllvo/vo/keyframe_policy.h"

namespace pllvo::vo {
namespace {

KeyframePolicyConfig defaults() {
  KeyframePolicyConfig c;
  c.min_tracked_points = 60;
  c.min_tracked_ratio = 0.5;
  c.max_interval_s = 1.0;
  c.min_interval_s = 0.25;
  c.line_angle_distance_deg = 8.0;
  return c;
}

FrameTrackingState frame(double t, int points, bool idle = false, std::optional<double> angle_distance = {}) {
  FrameTrackingState s;
  s.timestamp = t;
  s.tracked_points = points;
  s.backend_idle = idle;
  s.line_angle_distance_deg = angle_distance;
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

TEST(KeyframePolicy, LineTriggerFiresWhenTheOverlapAngleSetMovesAway) {
  KeyframePolicy policy(defaults());
  policy.start_keyframe(10.0, 300);
  EXPECT_EQ(policy.decide(frame(10.1, 300, true, 2.0)), KeyframeReason::kNone);
  EXPECT_EQ(policy.decide(frame(10.1, 300, true, 8.0)), KeyframeReason::kNone);
  EXPECT_EQ(policy.decide(frame(10.1, 300, true, 8.5)), KeyframeReason::kLineAngles);
  // No distance (lines off, or too few angles): the rule cannot fire.
  EXPECT_EQ(policy.decide(frame(10.1, 300, true, std::nullopt)), KeyframeReason::kNone);
}

TEST(KeyframePolicy, LineTriggerWaitsForAnIdleBackEndUnlessToldNotTo) {
  auto c = defaults();
  KeyframePolicy waits(c);
  waits.start_keyframe(10.0, 300);
  EXPECT_EQ(waits.decide(frame(10.1, 300, false, 8.5)), KeyframeReason::kNone);
  EXPECT_EQ(waits.decide(frame(10.1, 300, true, 8.5)), KeyframeReason::kLineAngles);
  // The rules that protect tracking do not wait.
  EXPECT_EQ(waits.decide(frame(10.1, 59, false, 8.5)), KeyframeReason::kFewPoints);
  c.line_trigger_when_idle = false;
  KeyframePolicy always(c);
  always.start_keyframe(10.0, 300);
  EXPECT_EQ(always.decide(frame(10.1, 300, false, 8.5)), KeyframeReason::kLineAngles);
}

TEST(KeyframePolicy, PointTriggerAwaitsTheKeyframeInFlightUnlessToldNotTo) {
  auto c = defaults();
  KeyframePolicy awaits(c);
  awaits.start_keyframe(10.0, 300);
  FrameTrackingState starving = frame(10.1, 40);
  EXPECT_EQ(awaits.decide(starving), KeyframeReason::kFewPoints);
  starving.keyframe_in_flight = true;
  EXPECT_EQ(awaits.decide(starving), KeyframeReason::kNone);
  FrameTrackingState degraded = frame(10.1, 100);  // under half the keyframe's 300
  degraded.keyframe_in_flight = true;
  EXPECT_EQ(awaits.decide(degraded), KeyframeReason::kNone);
  // The time rule still applies.
  FrameTrackingState late = frame(11.5, 40);
  late.keyframe_in_flight = true;
  EXPECT_EQ(awaits.decide(late), KeyframeReason::kMaxInterval);
  c.point_trigger_while_in_flight = true;
  KeyframePolicy always(c);
  always.start_keyframe(10.0, 300);
  EXPECT_EQ(always.decide(starving), KeyframeReason::kFewPoints);
  EXPECT_EQ(always.decide(degraded), KeyframeReason::kTrackingQuality);
}

TEST(KeyframePolicy, EachTriggerCanBeSwitchedOff) {
  auto c = defaults();
  c.use_point_trigger = false;
  c.use_time_trigger = false;
  c.use_line_trigger = false;
  KeyframePolicy policy(c);
  policy.start_keyframe(10.0, 300);
  EXPECT_EQ(policy.decide(frame(100.0, 1, true, 45.0)), KeyframeReason::kNone);
}

TEST(KeyframePolicy, PointTriggerTakesPrecedence) {
  KeyframePolicy policy(defaults());
  policy.start_keyframe(10.0, 300);
  EXPECT_EQ(policy.decide(frame(12.0, 10, true)), KeyframeReason::kFewPoints);
}

TEST(KeyframeReason, NamesAreStable) {
  EXPECT_EQ(to_string(KeyframeReason::kFewPoints), "few_points");
  EXPECT_EQ(to_string(KeyframeReason::kLineAngles), "line_angles");
  EXPECT_EQ(to_string(KeyframeReason::kRelocalisation), "relocalisation");
  // stats.json lists every reason but kNone under keyframes_by_reason.
  EXPECT_EQ(all_keyframe_reasons().size(), 7u);
}

}  // namespace
}  // namespace pllvo::vo
