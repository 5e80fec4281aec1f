#include "pllvo/vo/keyframe_policy.h"


namespace pllvo::vo {

std::string to_string(KeyframeReason reason) {
  switch (reason) {
    case KeyframeReason::kNone: return "none";
    case KeyframeReason::kInitialization: return "initialization";
    case KeyframeReason::kFewPoints: return "few_points";
    case KeyframeReason::kTrackingQuality: return "tracking_quality";
    case KeyframeReason::kMaxInterval: return "max_interval";
    case KeyframeReason::kIdleInterval: return "idle_interval";
    case KeyframeReason::kLineAngles: return "line_angles";
    case KeyframeReason::kRelocalisation: return "relocalisation";
  }
  return "unknown";
}

const std::vector<KeyframeReason>& all_keyframe_reasons() {
  static const std::vector<KeyframeReason> reasons = {
      KeyframeReason::kInitialization, KeyframeReason::kFewPoints,    KeyframeReason::kTrackingQuality,
      KeyframeReason::kMaxInterval,    KeyframeReason::kIdleInterval, KeyframeReason::kLineAngles,
      KeyframeReason::kRelocalisation};
  return reasons;
}

KeyframePolicy::KeyframePolicy(const KeyframePolicyConfig& config) : config_(config) {}

void KeyframePolicy::start_keyframe(double timestamp, int tracked_points) {
  has_reference_ = true;
  reference_time_ = timestamp;
  reference_points_ = tracked_points;
}

void KeyframePolicy::set_reference_points(int tracked_points) { reference_points_ = tracked_points; }

KeyframeReason KeyframePolicy::decide(const FrameTrackingState& frame) const {
  if (!has_reference_) return KeyframeReason::kInitialization;
  const auto& c = config_;
  // Order: the rules that protect tracking first, the periodic ones last.
  // A keyframe in flight brings new points when its result arrives; another one now would see
  // the same points a frame or two later and only lengthen the queue.
  const bool point_rule_may_fire = !frame.keyframe_in_flight || c.point_trigger_while_in_flight;
  if (c.use_point_trigger && point_rule_may_fire) {
    if (frame.tracked_points < c.min_tracked_points) return KeyframeReason::kFewPoints;
    if (reference_points_ > 0 &&
        frame.tracked_points < c.min_tracked_ratio * static_cast<double>(reference_points_))
      return KeyframeReason::kTrackingQuality;
  }
  if (c.use_line_trigger && (frame.backend_idle || !c.line_trigger_when_idle) && frame.line_angle_distance_deg &&
      *frame.line_angle_distance_deg > c.line_angle_distance_deg)
    return KeyframeReason::kLineAngles;
  const double elapsed = frame.timestamp - reference_time_;
  if (c.use_time_trigger) {
    if (elapsed >= c.max_interval_s) return KeyframeReason::kMaxInterval;
    if (frame.backend_idle && elapsed >= c.min_interval_s) return KeyframeReason::kIdleInterval;
  }
  return KeyframeReason::kNone;
}

}  // namespace pllvo::vo
