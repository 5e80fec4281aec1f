#include "pllvo/features/lines/lines_config.h"

namespace pllvo::lines {

void LinesConfig::load(const ConfigNode& node) {
  detector.load(node.child("detector"));
  tracker.load(node.child("tracker"));
  cross_constraint.load(node.child("cross_constraint"));
  overlap_angles.load(node.child("overlap_angles"));
  associator.load(node.child("associator"));
  stereo.load(node.child("stereo"));
  node.reject_unknown_keys();
}

LinesConfig load_lines_config(const std::filesystem::path& file) {
  LinesConfig config;
  config.load(ConfigNode::load_file(file));
  return config;
}

}  // namespace pllvo::lines
