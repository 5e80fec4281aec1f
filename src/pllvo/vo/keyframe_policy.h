#pragma once
// When to make a keyframe (paper 3.3). Three strategies, each with its own threshold and
// switch, and every decision names the rule that fired, so logs and stats show why.
#include <optional>
#include <string>
#include <vector>

#include "pllvo/vo/vo_config.h"

namespace pllvo::vo {

enum class KeyframeReason {
  kNone,
  kInitialization,    ///< first keyframe(s) of a map
  kFewPoints,         ///< (1) tracked points below the minimum count
  kTrackingQuality,   ///< (1) share of the keyframe's points still tracked below the ratio
                      ///<     (mono: once candidates have parallax, or map points run out)
  kMaxInterval,       ///< (2) too long since the last keyframe
  kIdleInterval,      ///< (2) back end idle and the minimum interval passed
  kLineAngles,        ///< (3) the line overlap-angle set changed beyond its threshold
  kRelocalisation,    ///< a monocular frame placed in the map before a loss: that map resumes
};

/// Stable lower-case name used in logs and stats.json.
std::string to_string(KeyframeReason reason);
/// Every reason except kNone, in declaration order (for counters).
const std::vector<KeyframeReason>& all_keyframe_reasons();

/// What the tracker knows about the current frame when it asks for a decision.
struct FrameTrackingState {
  double timestamp = 0;
  int tracked_points = 0;    ///< points tracked into this frame and kept by the pose solver
  bool backend_idle = true;  ///< the keyframe worker has nothing queued or running
  /// A keyframe was made whose result has not reached the tracker yet.
  bool keyframe_in_flight = false;
  /// Distance in degrees between the frame's set of line overlap angles and the keyframe's
  /// (lines::overlap_angle_distance, paper eq. 9); nullopt when lines are not used or the
  /// sets hold too few angles to describe the view.
  std::optional<double> line_angle_distance_deg;
};

class KeyframePolicy {
 public:
  explicit KeyframePolicy(const KeyframePolicyConfig& config);

  /// A keyframe was made at `timestamp`; later frames are compared with this state (the
  /// keyframe's overlap-angle set is kept by the caller, which measures the distance to it).
  void start_keyframe(double timestamp, int tracked_points);
  /// The keyframe's own points became trackable (after its detection finished on the worker):
  /// the tracking-quality ratio is measured against this count from now on.
  void set_reference_points(int tracked_points);

  KeyframeReason decide(const FrameTrackingState& frame) const;

  bool has_reference() const { return has_reference_; }
  double reference_time() const { return reference_time_; }
  int reference_points() const { return reference_points_; }

 private:
  KeyframePolicyConfig config_;
  bool has_reference_ = false;
  double reference_time_ = 0;
  int reference_points_ = 0;
};

}  // namespace pllvo::vo
