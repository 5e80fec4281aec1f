#pragma once
// Reads a YAML string key that must name one of a fixed set of choices (an enum).
#include <string>
#include <utility>
#include <vector>

#include "pllvo/common/yaml_config.h"

namespace pllvo::geometry {

template <typename Enum>
using Choices = std::vector<std::pair<std::string, Enum>>;

template <typename Enum>
std::string choice_name(Enum value, const Choices<Enum>& choices) {
  for (const auto& [name, e] : choices)
    if (e == value) return name;
  return "?";
}

/// Overwrites `value` when `key` is present; InputError naming the key and the valid
/// choices when the string names none of them.
template <typename Enum>
void get_choice(const ConfigNode& node, const std::string& key, Enum& value, const Choices<Enum>& choices) {
  if (!node.has(key)) {
    node.record_default(key, choice_name(value, choices));
    return;
  }
  std::string text;
  node.get(key, text);
  for (const auto& [name, e] : choices)
    if (name == text) {
      value = e;
      return;
    }
  std::string valid;
  for (const auto& c : choices) valid += (valid.empty() ? "" : ", ") + c.first;
  throw InputError(node.file(), node.path(key), "'" + text + "' is not one of: " + valid);
}


}  // namespace pllvo::geometry
