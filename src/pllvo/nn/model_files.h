#pragma once
// Where network weights are found. One documented order (docs/nn.md):
//   1. the path given in the configuration (a file, or a folder holding the file);
//      when given, it must exist: a wrong path is an error, not a silent fallback;
//   2. $PLLVO_MODELS/<file name>;
//   3. <repository>/models/<file name>.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace pllvo::nn {

inline constexpr const char* kSuperPointWeights = "superpoint_v1.safetensors";
inline constexpr const char* kLightGlueWeights = "superpoint_lightglue.safetensors";

struct WeightSearch {
  std::optional<std::filesystem::path> found;
  std::vector<std::filesystem::path> tried;  ///< every location looked at, in order

  /// "'superpoint_v1.safetensors' not found (looked in: a, b, c)".
  std::string not_found_message(const std::string& file_name) const;
};

/// Looks for `file_name` in the documented order. InputError when `configured` is set
/// but neither a file nor a folder holding `file_name`.
WeightSearch find_weights(const std::filesystem::path& configured, const std::string& file_name);

/// The repository's models/ folder (compiled in).
std::filesystem::path repository_models_dir();

}  // namespace pllvo::nn
