#pragma once
// All back-end parameters in one struct, loadable from YAML (config/backend.yaml).
#include <filesystem>

#include "pllvo/backend/pose_refiner.h"
#include "pllvo/backend/sliding_window_ba.h"
#include "pllvo/common/yaml_config.h"

namespace pllvo::backend {

struct BackendConfig {
  PoseRefinerConfig pose_refiner;
  BundleAdjustmentConfig bundle_adjustment;

  /// Overrides the keys present under `node`; InputError for unknown keys or bad values.
  void load(const ConfigNode& node);
  static BackendConfig load_file(const std::filesystem::path& file);
};

}  // namespace pllvo::backend
