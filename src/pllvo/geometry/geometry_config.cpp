#include "pllvo/geometry/geometry_config.h"

namespace pllvo::geometry {

void GeometryConfig::load(const ConfigNode& node) {
  point_triangulation.load(node.child("point_triangulation"));
  line_triangulation.load(node.child("line_triangulation"));
  pnp.load(node.child("pnp"));
  two_view.load(node.child("two_view"));
  stereo.load(node.child("stereo"));
  node.reject_unknown_keys();
}

GeometryConfig GeometryConfig::load_file(const std::filesystem::path& file) {
  GeometryConfig config;
  config.load(ConfigNode::load_file(file));
  return config;
}

}  // namespace pllvo::geometry
