#include "pllvo/backend/backend_config.h"

namespace pllvo::backend {

void BackendConfig::load(const ConfigNode& node) {
  pose_refiner.load(node.child("pose_refiner"));
  bundle_adjustment.load(node.child("bundle_adjustment"));
  node.reject_unknown_keys();
}

BackendConfig BackendConfig::load_file(const std::filesystem::path& file) {
  BackendConfig config;
  config.load(ConfigNode::load_file(file));
  return config;
}

}  // namespace pllvo::backend
