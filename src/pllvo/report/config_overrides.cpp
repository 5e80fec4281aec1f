#include "pllvo/report/config_overrides.h"

#include "pllvo/common/error.h"
#include "pllvo/common/yaml_config.h"

namespace pllvo::report {
namespace {

std::vector<std::string> split_key(const std::string& key) {
  std::vector<std::string> parts;
  size_t start = 0;
  while (true) {
    const size_t dot = key.find('.', start);
    parts.push_back(key.substr(start, dot == std::string::npos ? std::string::npos : dot - start));
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  return parts;
}

}  // namespace

ConfigOverride parse_override(const std::string& assignment) {
  const size_t eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError("override '" + assignment + "' must be key=value, e.g. frontend.type=orb");
  ConfigOverride o;
  o.key = assignment.substr(0, eq);
  try {
    o.value = YAML::Load(assignment.substr(eq + 1));
  } catch (const YAML::Exception& e) {
    throw InputError("override '" + assignment + "': cannot read the value as YAML (" + e.msg + ")");
  }
  if (!o.value || o.value.IsNull()) o.value = YAML::Node(std::string());  // "key=" sets an empty string
  return o;
}

void apply_override(YAML::Node& root, const ConfigOverride& o, const std::string& source) {
  const auto parts = split_key(o.key);
  for (const auto& p : parts)
    if (p.empty()) throw InputError(source, o.key, "empty part in the key");
  // yaml-cpp nodes are handles: walking with assignment would rebind, so recurse on copies of
  // the handles instead (they still refer to the same tree).
  YAML::Node node = root;
  for (size_t i = 0; i + 1 < parts.size(); ++i) {
    YAML::Node next = node[parts[i]];
    if (!next || next.IsNull()) {
      node[parts[i]] = YAML::Node(YAML::NodeType::Map);
      next = node[parts[i]];
    } else if (!next.IsMap()) {
      throw InputError(source, o.key, "'" + parts[i] + "' holds a value, not a section");
    }
    node.reset(next);
  }
  node[parts.back()] = YAML::Clone(o.value);
}

std::vector<ConfigOverride> flatten_overrides(const YAML::Node& mapping, const std::string& prefix) {
  std::vector<ConfigOverride> out;
  if (!mapping || mapping.IsNull()) return out;
  if (!mapping.IsMap()) throw InputError("overrides" + (prefix.empty() ? std::string() : " at " + prefix) +
                                         " must be a mapping of keys to values");
  for (const auto& kv : mapping) {
    const std::string key = (prefix.empty() ? "" : prefix + ".") + kv.first.as<std::string>();
    if (kv.second.IsMap() && kv.second.size() > 0) {
      auto inner = flatten_overrides(kv.second, key);
      out.insert(out.end(), inner.begin(), inner.end());
    } else {
      out.push_back({key, kv.second});
    }
  }
  return out;
}

vo::VoConfig make_vo_config(const YAML::Node& base, const std::vector<ConfigOverride>& overrides,
                            const std::string& source) {
  YAML::Node root = base && base.IsMap() ? YAML::Clone(base) : YAML::Node(YAML::NodeType::Map);
  for (const auto& o : overrides) apply_override(root, o, source);
  vo::VoConfig config;
  config.read(ConfigNode(root, source));
  config.validate(source);
  return config;
}

}  // namespace pllvo::report
