#include "pllvo/nn/nn_config.h"

namespace pllvo::nn {

NnConfig NnConfig::from_yaml(const ConfigNode& node) {
  NnConfig c;
  node.get("threads", c.threads);
  c.superpoint = SuperPointConfig::from_yaml(node.child("superpoint"));
  c.adaptive_threshold = AdaptiveThresholdConfig::from_yaml(node.child("adaptive_threshold"));
  c.matcher = MatcherConfig::from_yaml(node.child("matcher"));
  node.reject_unknown_keys();
  return c;
}

NnConfig NnConfig::load(const std::filesystem::path& file) { return from_yaml(ConfigNode::load_file(file)); }

}  // namespace pllvo::nn
