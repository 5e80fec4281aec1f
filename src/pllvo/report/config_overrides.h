#pragma once
// VO configurations built from a base YAML and generic `key=value` overrides with dotted keys
// (`frontend.type=orb`, `lines.cross_constraint.enabled=false`): a bench method is such a set
// of overrides, so a key the VO gains later works without code here. Unknown keys and bad
// values are InputErrors naming where the override came from.
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "pllvo/vo/vo_config.h"

namespace pllvo::report {

/// One override: a dotted key path and its value (a YAML scalar, list or mapping).
struct ConfigOverride {
  std::string key;
  YAML::Node value;
};

/// Parses "a.b.c=value"; the value is read as YAML ("false", "3", "orb", "[1, 2]").
/// InputError when there is no '=' or the key is empty.
ConfigOverride parse_override(const std::string& assignment);

/// Writes `value` at the dotted `key` of `root` (a mapping), creating the mappings on the way.
/// InputError (`source`, key) when a prefix of the key holds a non-mapping value.
void apply_override(YAML::Node& root, const ConfigOverride& o, const std::string& source);

/// The overrides of a YAML mapping, flattened to dotted keys ({a: {b: 1}} and {a.b: 1} alike).
std::vector<ConfigOverride> flatten_overrides(const YAML::Node& mapping, const std::string& prefix = "");

/// VoConfig from `base` (a VO YAML document, may be null) with the overrides applied in order,
/// read and validated; `source` names the origin in errors (e.g. "config/bench.yaml: method orb").
vo::VoConfig make_vo_config(const YAML::Node& base, const std::vector<ConfigOverride>& overrides,
                            const std::string& source);

}  // namespace pllvo::report
