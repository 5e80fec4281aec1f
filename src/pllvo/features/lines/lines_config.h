#pragma once
// All settings of the line front end in one struct, loadable from YAML (config/lines.yaml):
//   detector: {...}  tracker: {...}  cross_constraint: {...}  overlap_angles: {...}  associator: {...}  stereo: {...}
// Every key is optional (defaults in code); unknown keys are an error.
#include <filesystem>

#include "pllvo/common/yaml_config.h"
#include "pllvo/features/lines/cross_constraint.h"
#include "pllvo/features/lines/line_associator.h"
#include "pllvo/features/lines/line_detector.h"
#include "pllvo/features/lines/line_tracker.h"
#include "pllvo/features/lines/overlap_angles.h"
#include "pllvo/features/lines/stereo_line_matcher.h"

namespace pllvo::lines {

struct LinesConfig {
  LineDetectorConfig detector;
  LineTrackerConfig tracker;
  CrossConstraintConfig cross_constraint;
  OverlapAngleConfig overlap_angles;
  LineAssociatorConfig associator;
  StereoLineMatcherConfig stereo;

  void load(const ConfigNode& node);
};

/// Reads a lines YAML file; InputError naming the file and key on a bad or unknown value.
LinesConfig load_lines_config(const std::filesystem::path& file);

}  // namespace pllvo::lines
