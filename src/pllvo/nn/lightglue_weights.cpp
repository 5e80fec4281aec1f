#include <regex>

#include <nlohmann/json.hpp>

#include "pllvo/common/error.h"
#include "pllvo/nn/lightglue.h"

namespace pllvo::nn {

LightGlueConfig LightGlueConfig::from_yaml(const ConfigNode& node) {
  LightGlueConfig c;
  std::string weights;
  node.get("weights", weights);
  c.weights = weights;
  std::vector<std::string> overrides;
  node.get("weight_overrides", overrides);
  for (const auto& o : overrides) c.weight_overrides.emplace_back(o);
  node.get("filter_threshold", c.filter_threshold);
  node.get("depth_confidence", c.depth_confidence);
  node.get("width_confidence", c.width_confidence);
  node.get("pruning_keypoint_threshold", c.pruning_keypoint_threshold);
  node.reject_unknown_keys();
  if (const auto [key, what] = c.problem(); !key.empty()) throw InputError(node.file(), node.path(key), what);
  return c;
}

std::pair<std::string, std::string> LightGlueConfig::problem() const {
  if (!(filter_threshold >= 0.0f && filter_threshold < 1.0f)) return {"filter_threshold", "must be in [0, 1)"};
  if (!(depth_confidence <= 1.0f)) return {"depth_confidence", "must be <= 1 (<= 0 turns it off)"};
  if (!(width_confidence <= 1.0f)) return {"width_confidence", "must be <= 1 (<= 0 turns it off)"};
  return {};
}

void LightGlueConfig::validate() const {
  if (const auto [key, what] = problem(); !key.empty()) throw InputError("LightGlue setting " + key + ": " + what);
}

namespace {

// The released checkpoints name layers self_attn.{i}. / cross_attn.{i}.; the official loader
// renames them to transformers.{i}.self_attn. / .cross_attn. (done here exactly, by prefix).
std::string official_name(const std::string& name) {
  static const std::regex pattern(R"(^(self_attn|cross_attn)\.(\d+)\.(.*)$)");
  std::smatch m;
  if (std::regex_match(name, m, pattern)) return "transformers." + m[2].str() + "." + m[1].str() + "." + m[3].str();
  return name;
}

}  // namespace

SafeTensors with_official_names(const SafeTensors& in) {
  SafeTensors out;
  out.set_file(in.file());
  out.metadata() = in.metadata();
  for (const auto& name : in.names()) out.set(official_name(name), in.at(name));
  return out;
}

namespace {

std::int64_t dim(const SafeTensors& st, const std::string& name, std::size_t rank, std::size_t axis) {
  if (!st.contains(name)) throw InputError(st.file(), name, "tensor missing (not a LightGlue weight file?)");
  const auto& shape = st.at(name).shape;
  if (shape.size() != rank) throw InputError(st.file(), name, "rank " + std::to_string(shape.size()) + ", expected " + std::to_string(rank));
  return shape[axis];
}

}  // namespace

LightGlueArchitecture lightglue_architecture(const SafeTensors& raw) {
  const SafeTensors st = with_official_names(raw);
  LightGlueArchitecture a;
  a.descriptor_dim = static_cast<int>(dim(st, "transformers.0.self_attn.out_proj.weight", 2, 0));
  const auto wr_rows = dim(st, "posenc.Wr.weight", 2, 0);
  const auto wr_cols = dim(st, "posenc.Wr.weight", 2, 1);
  if (wr_cols != 2 && wr_cols != 4) throw InputError(st.file(), "posenc.Wr.weight", "expected 2 (or 4) input columns");
  a.add_scale_ori = wr_cols == 4;
  const auto head_dim = 2 * wr_rows;
  if (head_dim <= 0 || a.descriptor_dim % head_dim != 0)
    throw InputError(st.file(), "posenc.Wr.weight", "rows do not divide the descriptor dimension into heads");
  a.num_heads = static_cast<int>(a.descriptor_dim / head_dim);
  a.n_layers = 0;
  while (st.contains("transformers." + std::to_string(a.n_layers) + ".self_attn.Wqkv.weight")) ++a.n_layers;
  a.input_dim = st.contains("input_proj.weight") ? static_cast<int>(dim(st, "input_proj.weight", 2, 1)) : a.descriptor_dim;

  if (const auto it = st.metadata().find("config"); it != st.metadata().end()) {
    nlohmann::json config;
    try {
      config = nlohmann::json::parse(it->second);
    } catch (const nlohmann::json::exception& e) {
      throw InputError(st.file(), "__metadata__.config", std::string("malformed JSON: ") + e.what());
    }
    const auto check = [&](const char* key, long value) {
      if (!config.contains(key) || config[key].is_null()) return;
      if (!config[key].is_number_integer() && !config[key].is_boolean())
        throw InputError(st.file(), std::string("__metadata__.config.") + key, "not a number");
      const long stored = config[key].is_boolean() ? long(config[key].get<bool>()) : config[key].get<long>();
      if (stored != value)
        throw InputError(st.file(), std::string("__metadata__.config.") + key,
                         "says " + std::to_string(stored) + " but the tensors hold " + std::to_string(value));
    };
    check("input_dim", a.input_dim);
    check("descriptor_dim", a.descriptor_dim);
    check("n_layers", a.n_layers);
    check("num_heads", a.num_heads);
    check("add_scale_ori", a.add_scale_ori);
  }
  if (a.n_layers == 0) throw InputError(st.file(), "transformers.0.self_attn.Wqkv.weight", "tensor missing");
  return a;
}

SafeTensors load_weights_with_overrides(const std::filesystem::path& file,
                                        const std::vector<std::filesystem::path>& overrides) {
  SafeTensors st = SafeTensors::load(file);
  for (const auto& o : overrides) {
    const auto extra = SafeTensors::load(o);
    for (const auto& name : extra.names()) st.set(name, extra.at(name));
  }
  return st;
}

}  // namespace pllvo::nn
