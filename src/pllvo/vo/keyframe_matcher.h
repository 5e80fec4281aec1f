#pragma once
// Matching of keyframe points with the previous keyframe's: Hamming + ratio test for binary
// descriptors (ORB baselines), mutual nearest neighbour or LightGlue for SuperPoint.
#include <memory>
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

class KeyframeMatcher {
 public:
  virtual ~KeyframeMatcher() = default;
  virtual std::string name() const = 0;
  /// One-to-one matches between `a` and `b` (images of size `image_size`).
  virtual std::vector<PointMatch> match(const PointFeatures& a, const PointFeatures& b, cv::Size image_size) = 0;
};

/// Picks the matcher for the front end's descriptors and the mapping config.
std::unique_ptr<KeyframeMatcher> make_keyframe_matcher(const MappingConfig& config, const std::string& frontend);

}  // namespace pllvo::vo
