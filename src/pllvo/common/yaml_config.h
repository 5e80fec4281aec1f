#pragma once
// Helpers for config structs loaded from YAML. Every struct has defaults in code;
// a YAML file only overrides the keys it names. Unknown keys are an error (a typo
// must not silently fall back to a default), and so is a value of the wrong type.
#include <filesystem>
#include <limits>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "pllvo/common/error.h"

namespace pllvo {

/// A YAML mapping together with the file it came from and its key path, so that
/// every error can name "file: key.path".
class ConfigNode {
 public:
  ConfigNode(YAML::Node node, std::filesystem::path file, std::string prefix = "");

  /// Loads a whole file; missing or unparsable files raise InputError with the line.
  static ConfigNode load_file(const std::filesystem::path& file);

  /// A key path and its default, as a YAML scalar or flow sequence.
  struct Default {
    std::string key, value;
  };
  /// An empty mapping that records every key a load() asks for, with the value it holds
  /// then (the struct's default), in the order asked: the configuration reference comes
  /// from the code that reads the keys (`pllvo config --dump`).
  static ConfigNode recording();
  /// The keys recorded so far (empty unless made by recording()).
  std::vector<Default> recorded() const { return recorder_ ? *recorder_ : std::vector<Default>{}; }
  /// Records `key` with a default given as text (keys read by other means, e.g. enums).
  void record_default(const std::string& key, const std::string& text) const {
    if (recorder_ && !node_[key]) recorder_->push_back({path(key), text});
  }

  bool has(const std::string& key) const;
  ConfigNode child(const std::string& key) const;  ///< an empty mapping when absent

  /// Overwrites `value` when `key` is present; raises InputError on a bad value.
  template <typename T>
  void get(const std::string& key, T& value) const {
    used_.insert(key);
    if (!node_[key]) {
      if (recorder_) recorder_->push_back({path(key), to_text(value)});
      return;
    }
    try {
      value = node_[key].as<T>();
    } catch (const YAML::Exception&) {
      throw InputError(file_, path(key), "cannot read the value as " + type_name<T>());
    }
  }

  /// Required value: raises InputError naming the key when it is absent.
  template <typename T>
  T require(const std::string& key) const {
    if (!node_[key]) throw InputError(file_, path(key), "missing");
    T value{};
    get(key, value);
    return value;
  }

  /// Raises InputError for keys present in the file that no get()/child() asked for.
  void reject_unknown_keys() const;

  const std::filesystem::path& file() const { return file_; }
  std::string path(const std::string& key) const { return prefix_.empty() ? key : prefix_ + "." + key; }
  const YAML::Node& raw() const { return node_; }

 private:
  template <typename T>
  static std::string type_name();
  template <typename T>
  static std::string to_text(const T& value);

  YAML::Node node_;
  std::filesystem::path file_;
  std::string prefix_;
  mutable std::set<std::string> used_;
  std::shared_ptr<std::vector<Default>> recorder_;  ///< shared by a recording node's children
};

template <typename T>
std::string ConfigNode::to_text(const T& value) {
  std::ostringstream out;
  if constexpr (std::is_floating_point_v<T>) out.precision(std::numeric_limits<T>::digits10);  // 0.7f: "0.7"
  if constexpr (std::is_same_v<T, bool>) out << (value ? "true" : "false");
  else if constexpr (std::is_same_v<T, std::string>) out << (value.empty() ? "\"\"" : value);
  else if constexpr (std::is_arithmetic_v<T>) out << value;
  else {
    out << "[";
    for (size_t i = 0; i < value.size(); ++i) out << (i ? ", " : "") << to_text(value[i]);
    out << "]";
  }
  return out.str();
}

template <typename T>
std::string ConfigNode::type_name() {
  if constexpr (std::is_same_v<T, bool>) return "a boolean";
  else if constexpr (std::is_integral_v<T>) return "an integer";
  else if constexpr (std::is_floating_point_v<T>) return "a number";
  else if constexpr (std::is_same_v<T, std::string>) return "a string";
  else return "the expected type";
}

}  // namespace pllvo
