#pragma once
// All geometry parameters in one struct, loadable from YAML (config/geometry.yaml).
#include <filesystem>

#include "pllvo/common/yaml_config.h"
#include "pllvo/geometry/line_triangulation.h"
#include "pllvo/geometry/pnp.h"
#include "pllvo/geometry/stereo_triangulation.h"
#include "pllvo/geometry/triangulation.h"
#include "pllvo/geometry/two_view.h"

namespace pllvo::geometry {

struct GeometryConfig {
  PointTriangulationConfig point_triangulation;
  LineTriangulationConfig line_triangulation;
  PnpConfig pnp;
  TwoViewConfig two_view;
  StereoTriangulationConfig stereo;

  /// Overrides the keys present under `node` (sections as the member names above);
  /// InputError for unknown keys or bad values.
  void load(const ConfigNode& node);
  static GeometryConfig load_file(const std::filesystem::path& file);
};

}  // namespace pllvo::geometry
