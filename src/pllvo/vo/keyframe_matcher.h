#pragma once
// Matching of keyframe points with the previous keyframe's: Hamming + ratio test for binary
// descriptors (ORB baselines), mutual nearest neighbour or LightGlue for SuperPoint.
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "pllvo/vo/point_frontend.h"
#include "pllvo/vo/vo_config.h"

namespace pllvo::vo {

struct PointMatch {
  int a = -1, b = -1;  ///< indices into the two feature sets
  float score = 0;     ///< matcher confidence or descriptor distance (matcher-specific)
};

/// How much of an adaptive matcher (LightGlue) the last match ran.
struct MatchEffort {
  int layers_run = 0;        ///< layers before the confidence exit (the model's depth: none)
  float pruned_share = 0;    ///< points dropped as unmatchable before the last layer run
};

class KeyframeMatcher {
 public:
  virtual ~KeyframeMatcher() = default;
  virtual std::string name() const = 0;
  /// One-to-one matches between `a` and `b` (images of size `image_size`).
  virtual std::vector<PointMatch> match(const PointFeatures& a, const PointFeatures& b, cv::Size image_size) = 0;
  /// The adaptive depth and width of the last match(); none for fixed-cost matchers.
  virtual std::optional<MatchEffort> last_effort() const { return std::nullopt; }
};

/// `matcher` on the rows of `a` and `b` not flagged in `skip_a` / `skip_b` (one flag per row);
/// the matches index `a` and `b` themselves.
std::vector<PointMatch> match_unflagged(KeyframeMatcher& matcher, const PointFeatures& a, const std::vector<char>& skip_a,
                                        const PointFeatures& b, const std::vector<char>& skip_b, cv::Size image_size);

/// Picks the matcher for the front end's descriptors and the mapping config.
std::unique_ptr<KeyframeMatcher> make_keyframe_matcher(const MappingConfig& config, const std::string& frontend);

}  // namespace pllvo::vo
