#include "pllvo/vo/keyframe_policy.h"

#include <algorithm>
#include <cmath>

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
  }
  return "unknown";
}

const std::vector<KeyframeReason>& all_keyframe_reasons() {
  static const std::vector<KeyframeReason> reasons = {
      KeyframeReason::kInitialization, KeyframeReason::kFewPoints,    KeyframeReason::kTrackingQuality,
      KeyframeReason::kMaxInterval,    KeyframeReason::kIdleInterval, KeyframeReason::kLineAngles};
  return reasons;
}

double angle_set_change(std::vector<double> reference, std::vector<double> current, double tolerance) {
  if (reference.empty() && current.empty()) return 0.0;
  std::sort(reference.begin(), reference.end());
  std::sort(current.begin(), current.end());
  // On sorted values, pairing greedily from the smallest gives a maximum one-to-one
  // matching under an absolute tolerance.
  size_t i = 0, j = 0, matched = 0;
  while (i < reference.size() && j < current.size()) {
    if (std::abs(reference[i] - current[j]) <= tolerance) {
      ++matched, ++i, ++j;
    } else if (reference[i] < current[j]) {
      ++i;
    } else {
      ++j;
    }
  }
  const double larger = static_cast<double>(std::max(reference.size(), current.size()));
  return 1.0 - static_cast<double>(matched) / larger;
}

KeyframePolicy::KeyframePolicy(const KeyframePolicyConfig& config) : config_(config) {}

void KeyframePolicy::start_keyframe(double timestamp, int tracked_points, std::vector<double> line_angles) {
  has_reference_ = true;
  reference_time_ = timestamp;
  reference_points_ = tracked_points;
  reference_angles_ = std::move(line_angles);
}

void KeyframePolicy::set_reference_points(int tracked_points) { reference_points_ = tracked_points; }

KeyframeReason KeyframePolicy::decide(const FrameTrackingState& frame) const {
  if (!has_reference_) return KeyframeReason::kInitialization;
  const auto& c = config_;
  // Order: the rules that protect tracking first, the periodic ones last.
  if (c.use_point_trigger) {
    if (frame.tracked_points < c.min_tracked_points) return KeyframeReason::kFewPoints;
    if (reference_points_ > 0 &&
        frame.tracked_points < c.min_tracked_ratio * static_cast<double>(reference_points_))
      return KeyframeReason::kTrackingQuality;
  }
  if (c.use_line_trigger && frame.line_angles) {
    const auto& angles = *frame.line_angles;
    const int larger = static_cast<int>(std::max(angles.size(), reference_angles_.size()));
    if (larger >= c.line_min_angles) {
      const double tol = c.line_angle_tolerance_deg * M_PI / 180.0;
      if (angle_set_change(reference_angles_, angles, tol) > c.line_angle_change) return KeyframeReason::kLineAngles;
    }
  }
  const double elapsed = frame.timestamp - reference_time_;
  if (c.use_time_trigger) {
    if (elapsed >= c.max_interval_s) return KeyframeReason::kMaxInterval;
    if (frame.backend_idle && elapsed >= c.min_interval_s) return KeyframeReason::kIdleInterval;
  }
  return KeyframeReason::kNone;
}

}  // namespace pllvo::vo
