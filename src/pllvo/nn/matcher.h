#pragma once
// One interface for the point matchers, and the documented fallback: LightGlue when its
// weights are found, otherwise mutual nearest neighbours with a warning saying so.
#include <memory>
#include <string>

#include "pllvo/common/yaml_config.h"
#include "pllvo/nn/features.h"
#include "pllvo/nn/lightglue.h"
#include "pllvo/nn/mnn_matcher.h"

namespace pllvo::nn {

class FeatureMatcher {
 public:
  virtual ~FeatureMatcher() = default;
  virtual Matches match(const Features& f0, const Features& f1) const = 0;
  virtual std::string name() const = 0;  ///< "lightglue" | "mnn"
};

struct MatcherConfig {
  std::string type = "lightglue";  ///< lightglue | mnn
  LightGlueConfig lightglue;
  MnnConfig mnn;

  static MatcherConfig from_yaml(const ConfigNode& node);  ///< keys: type, lightglue, mnn
};

/// Applies the documented fallback: type "lightglue" with no weights found (and no explicit
/// path configured) becomes "mnn", with a warning logged and returned in `notice`; otherwise
/// lightglue.weights is set to the file found. An explicitly configured path that does not
/// exist is an InputError, never a silent fallback.
MatcherConfig resolve_matcher(const MatcherConfig& config, std::string* notice = nullptr);

/// The configured matcher (after resolve_matcher). type "lightglue" with no weights found (and no explicit path
/// configured) logs a warning naming where it looked and returns the MNN matcher.
std::unique_ptr<FeatureMatcher> make_matcher(const MatcherConfig& config, std::string* notice = nullptr);

}  // namespace pllvo::nn
