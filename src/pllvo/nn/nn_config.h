#pragma once
// All settings of the learned front end in one struct, loadable from YAML (config/nn.yaml
// lists every key with its default).
#include <filesystem>

#include "pllvo/common/yaml_config.h"
#include "pllvo/nn/adaptive_threshold.h"
#include "pllvo/nn/matcher.h"
#include "pllvo/nn/superpoint.h"

namespace pllvo::nn {

struct NnConfig {
  int threads = 0;  ///< LibTorch + OpenBLAS threads (set_num_threads); 0 keeps the runtime default
  SuperPointConfig superpoint;
  AdaptiveThresholdConfig adaptive_threshold;
  MatcherConfig matcher;

  /// Keys: threads, superpoint, adaptive_threshold, matcher (each optional).
  static NnConfig from_yaml(const ConfigNode& node);
  static NnConfig load(const std::filesystem::path& file);
};

}  // namespace pllvo::nn
