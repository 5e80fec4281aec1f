#include "pllvo/report/bench_methods.h"

#include <set>

#include "pllvo/common/error.h"
#include "pllvo/common/yaml_config.h"

namespace pllvo::report {

std::vector<BenchMethod> BenchMethodTable::select(const std::vector<std::string>& names,
                                                  const std::filesystem::path& file) const {
  const auto& wanted = names.empty() ? default_methods : names;
  if (wanted.empty()) return methods;
  std::vector<BenchMethod> out;
  for (const auto& n : wanted) {
    bool found = false;
    for (const auto& m : methods)
      if (m.name == n) out.push_back(m), found = true;
    if (!found) {
      std::string known;
      for (const auto& m : methods) known += (known.empty() ? "" : ", ") + m.name;
      throw InputError(file, "methods", "no method named '" + n + "' (known: " + known + ")");
    }
  }
  return out;
}

BenchMethodTable load_bench_methods(const std::filesystem::path& file) {
  const ConfigNode root = ConfigNode::load_file(file);
  BenchMethodTable table;
  root.get("speed_baseline", table.speed_baseline);
  root.get("default_methods", table.default_methods);
  YAML::Node common, methods;
  root.get("common", common);
  root.get("methods", methods);
  try {
    table.common = flatten_overrides(common);
  } catch (const InputError& e) {
    throw InputError(file, "common", e.what());
  }
  if (!methods || !methods.IsSequence() || methods.size() == 0)
    throw InputError(file, "methods", "must be a non-empty list of {name, description, set}");
  std::set<std::string> names;
  for (size_t i = 0; i < methods.size(); ++i) {
    const std::string where = "methods[" + std::to_string(i) + "]";
    if (!methods[i].IsMap()) throw InputError(file, where, "must be a mapping {name, description, set}");
    const ConfigNode node(methods[i], file, where);
    BenchMethod m;
    m.name = node.require<std::string>("name");
    node.get("description", m.description);
    if (!names.insert(m.name).second) throw InputError(file, node.path("name"), "duplicate method '" + m.name + "'");
    YAML::Node set;
    node.get("set", set);
    try {
      m.overrides = flatten_overrides(set);
    } catch (const InputError& e) {
      throw InputError(file, node.path("set"), e.what());
    }
    node.reject_unknown_keys();
    table.methods.push_back(std::move(m));
  }
  root.reject_unknown_keys();
  for (const auto& n : table.default_methods)
    if (!names.count(n)) throw InputError(file, "default_methods", "no method named '" + n + "'");
  if (!names.count(table.speed_baseline))
    throw InputError(file, "speed_baseline", "no method named '" + table.speed_baseline + "'");
  return table;
}

}  // namespace pllvo::report
