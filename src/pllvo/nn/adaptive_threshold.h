#pragma once
// Adaptive SuperPoint score threshold (PLL-VO, section 3.2). A fixed threshold gives few,
// clustered points in dark or flat frames (scores drop with contrast) and floods rich ones.
// The rule, per frame, on the threshold-independent candidates (NMS maxima; the network
// runs once):
//   target     N = target_keypoints * g (g: matching feedback, below)
//   t_count    = the score of the (N+1)-th best candidate: score > t_count keeps N points
//                (min_threshold when there are fewer candidates above it);
//   t_cover    = the highest threshold that still leaves a point in min_occupancy of the
//                textured grid cells (cells with any candidate above min_threshold);
//   t          = clamp(min(t_count, t_cover), min_threshold, max_threshold);
//   keypoints  = candidates with score > t, at most max_keypoints (best by score).
// Matching feedback: after a frame is matched, report_matches(matched, keypoints): when
// fewer than poor_matches or a share below poor_ratio matched, g *= gain_step (<= max_gain);
// when at least good_matches and a share above good_ratio matched, g /= gain_step (>= min_gain).
// Details and measurements: docs/nn.md.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "pllvo/common/yaml_config.h"
#include "pllvo/nn/features.h"
#include "pllvo/nn/superpoint_postprocess.h"

namespace pllvo::nn {

class SuperPoint;

struct AdaptiveThresholdConfig {
  int target_keypoints = 500;
  int max_keypoints = 1000;       ///< hard cap against floods (<= 0: none)
  float min_threshold = 0.0005f;  ///< noise floor: never keep weaker points (LightGlue's default threshold)
  float max_threshold = 0.2f;     ///< never demand more than this
  int grid_cols = 8;              ///< occupancy grid over the image
  int grid_rows = 6;
  float min_occupancy = 0.7f;     ///< share of textured cells that must keep a point
  int poor_matches = 80;          ///< feedback: a frame with fewer matches matched poorly...
  float poor_ratio = 0.2f;        ///< ...or with a smaller share of its keypoints matched
  int good_matches = 200;         ///< a frame with at least this many matches...
  float good_ratio = 0.5f;        ///< ...and a larger share matched well
  float gain_step = 1.25f;
  float min_gain = 0.5f;
  float max_gain = 2.0f;

  static AdaptiveThresholdConfig from_yaml(const ConfigNode& node);
  /// {key, problem} of the first invalid setting; empty when all are valid.
  std::pair<std::string, std::string> problem() const;
  void validate() const;  ///< InputError naming the key
};

/// What the rule chose for one frame (for logs and tests).
struct ThresholdDecision {
  float threshold = 0;
  float count_threshold = 0;
  float coverage_threshold = 0;
  int target = 0;              ///< N = target_keypoints * gain
  int selected = 0;            ///< keypoints kept
  int textured_cells = 0;
  float occupancy = 0;         ///< share of textured cells holding a kept keypoint
};

class AdaptiveThreshold {
 public:
  explicit AdaptiveThreshold(AdaptiveThresholdConfig config = {});

  /// Chooses the frame's threshold and returns the selected candidate indices (row-major
  /// order, or descending score when max_keypoints cut them).
  std::vector<std::int32_t> select(const KeypointCandidates& candidates, ThresholdDecision* decision = nullptr) const;

  /// Network + adaptive selection + descriptors.
  Features detect(const SuperPoint& superpoint, const cv::Mat& image, ThresholdDecision* decision = nullptr) const;

  /// Feedback from matching the last frame: `matched` (inlier) matches of its `keypoints`.
  void report_matches(int matched, int keypoints);

  float gain() const { return gain_; }
  int target() const;
  const AdaptiveThresholdConfig& config() const { return config_; }

 private:
  AdaptiveThresholdConfig config_;
  float gain_ = 1.0f;
};

/// Share of the textured cells of a grid holding at least one of `selected`; a cell is
/// textured when some candidate in it scores above `floor`. Returns {occupancy, textured}.
std::pair<float, int> grid_occupancy(const KeypointCandidates& candidates, const std::vector<std::int32_t>& selected,
                                     int grid_cols, int grid_rows, float floor);

}  // namespace pllvo::nn
