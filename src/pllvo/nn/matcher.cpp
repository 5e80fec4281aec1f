#include "pllvo/nn/matcher.h"

#include <spdlog/spdlog.h>

#include "pllvo/common/error.h"
#include "pllvo/nn/model_files.h"

namespace pllvo::nn {
namespace {

class LightGlueMatcher : public FeatureMatcher {
 public:
  explicit LightGlueMatcher(LightGlue lightglue) : lightglue_(std::move(lightglue)) {}
  Matches match(const Features& f0, const Features& f1) const override {
    auto result = lightglue_.match(f0, f1);
    result.matches.layers_run = result.stop;
    const auto points = result.prune0.size() + result.prune1.size();
    if (points > 0) {
      const auto pruned = (result.prune0.array() < result.stop).count() + (result.prune1.array() < result.stop).count();
      result.matches.pruned_share = static_cast<float>(pruned) / static_cast<float>(points);
    }
    return result.matches;
  }
  std::string name() const override { return "lightglue"; }

 private:
  LightGlue lightglue_;
};

class MnnMatcher : public FeatureMatcher {
 public:
  explicit MnnMatcher(MnnConfig config) : config_(config) {}
  Matches match(const Features& f0, const Features& f1) const override { return match_mutual_nearest(f0, f1, config_); }
  std::string name() const override { return "mnn"; }

 private:
  MnnConfig config_;
};

}  // namespace

MatcherConfig MatcherConfig::from_yaml(const ConfigNode& node) {
  MatcherConfig c;
  node.get("type", c.type);
  if (c.type != "lightglue" && c.type != "mnn") throw InputError(node.file(), node.path("type"), "must be lightglue or mnn");
  c.lightglue = LightGlueConfig::from_yaml(node.child("lightglue"));
  c.mnn = MnnConfig::from_yaml(node.child("mnn"));
  node.reject_unknown_keys();
  return c;
}

MatcherConfig resolve_matcher(const MatcherConfig& config, std::string* notice) {
  if (notice) notice->clear();
  MatcherConfig resolved = config;
  if (config.type == "mnn") return resolved;
  if (config.type != "lightglue") throw InputError("matcher type '" + config.type + "' unknown (lightglue or mnn)");
  const auto search = find_weights(config.lightglue.weights, lightglue_weight_names());  // throws for a wrong explicit path
  if (search.found) {
    resolved.lightglue.weights = *search.found;
    return resolved;
  }
  const std::string message = "LightGlue weights " + search.not_found_message() +
                              "; falling back to the mutual-nearest-neighbour matcher (see docs/nn.md for the weights)";
  spdlog::warn("{}", message);
  if (notice) *notice = message;
  resolved.type = "mnn";
  return resolved;
}

std::unique_ptr<FeatureMatcher> make_matcher(const MatcherConfig& config, std::string* notice) {
  const MatcherConfig resolved = resolve_matcher(config, notice);
  if (resolved.type == "mnn") return std::make_unique<MnnMatcher>(resolved.mnn);
  return std::make_unique<LightGlueMatcher>(LightGlue(resolved.lightglue));
}

}  // namespace pllvo::nn
