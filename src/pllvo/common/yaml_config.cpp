#include "pllvo/common/yaml_config.h"

#include <fstream>

namespace pllvo {

ConfigNode::ConfigNode(YAML::Node node, std::filesystem::path file, std::string prefix)
    : node_(std::move(node)), file_(std::move(file)), prefix_(std::move(prefix)) {}

ConfigNode ConfigNode::load_file(const std::filesystem::path& file) {
  if (!std::filesystem::is_regular_file(file)) throw InputError(file, "file not found");
  YAML::Node root;
  try {
    root = YAML::LoadFile(file.string());
  } catch (const YAML::ParserException& e) {
    throw InputError(file, e.mark.line + 1, "malformed YAML: " + e.msg);
  } catch (const YAML::Exception& e) {
    throw InputError(file, std::string("cannot read YAML: ") + e.what());
  }
  if (root.IsNull()) root = YAML::Node(YAML::NodeType::Map);
  if (!root.IsMap()) throw InputError(file, 1, "expected a YAML mapping at the top level");
  return ConfigNode(root, file);
}

ConfigNode ConfigNode::recording() {
  ConfigNode node(YAML::Node(YAML::NodeType::Map), "(defaults)");
  node.recorder_ = std::make_shared<std::vector<Default>>();
  return node;
}

bool ConfigNode::has(const std::string& key) const { return static_cast<bool>(node_[key]); }

ConfigNode ConfigNode::child(const std::string& key) const {
  used_.insert(key);
  YAML::Node sub = node_[key];
  if (!sub) {
    ConfigNode empty(YAML::Node(YAML::NodeType::Map), file_, path(key));
    empty.recorder_ = recorder_;
    return empty;
  }
  if (!sub.IsMap()) throw InputError(file_, path(key), "expected a mapping");
  ConfigNode node(sub, file_, path(key));
  node.recorder_ = recorder_;
  return node;
}

void ConfigNode::reject_unknown_keys() const {
  for (const auto& kv : node_) {
    const auto key = kv.first.as<std::string>();
    if (!used_.count(key)) throw InputError(file_, path(key), "unknown key");
  }
}

}  // namespace pllvo
