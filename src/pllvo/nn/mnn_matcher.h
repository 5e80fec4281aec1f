#pragma once
// Mutual nearest neighbours on L2-normalised descriptors: the baseline matcher and the
// fallback when no LightGlue weights are available. Same rules as hloc's nearest_neighbor
// matcher: squared distance 2 (1 - cos), optional ratio test and distance threshold.
#include "pllvo/common/yaml_config.h"
#include "pllvo/nn/features.h"

namespace pllvo::nn {

struct MnnConfig {
  bool mutual = true;           ///< keep only pairs that are each other's nearest neighbour
  /// Lowe's ratio test on L2 distances, d1 <= ratio * d2; <= 0 turns it off.
  float ratio_threshold = 0.0f;
  /// Keep pairs with L2 distance <= this (unit descriptors: 0..2); <= 0 turns it off.
  /// 0.7 is hloc's setting for SuperPoint.
  float distance_threshold = 0.7f;

  static MnnConfig from_yaml(const ConfigNode& node);
};

/// Matches with scores = cosine similarity. Descriptor sizes must agree (InputError).
Matches match_mutual_nearest(const Features& f0, const Features& f1, const MnnConfig& config);

}  // namespace pllvo::nn
