#pragma once
// Where network weights are found. One documented order (docs/nn.md):
//   1. the path given in the configuration (a file, or a folder holding one of the files);
//      when given, it must exist: a wrong path is an error, not a silent fallback;
//   2. else one folder: $PLLVO_MODELS when set (it replaces the default folder, so a user or a
//      test can point pllvo at exactly the weights it means), else the installed models of an
//      installed program (<prefix>/share/pllvo/models beside <prefix>/bin/), else
//      <repository>/models/. A program linked against the installed library gets the installed
//      folder through the library API (pllvo::OdometryOptions::models_dir).
// In that folder the file names are tried in order: the official weights under their usual name
// first (a user who converted them asked for them), then pllvo's own trained weights.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace pllvo::nn {

inline constexpr const char* kSuperPointWeights = "superpoint_v1.safetensors";        ///< official, converted
inline constexpr const char* kLightGlueWeights = "superpoint_lightglue.safetensors";  ///< official, converted
inline constexpr const char* kPllvoSuperPointWeights = "pllvo_superpoint_v1.safetensors";  ///< pllvo's, shipped
inline constexpr const char* kPllvoLightGlueWeights = "pllvo_lightglue_v1.safetensors";    ///< pllvo's, shipped

/// The file names looked for, in order.
std::vector<std::string> superpoint_weight_names();
std::vector<std::string> lightglue_weight_names();

struct WeightSearch {
  std::optional<std::filesystem::path> found;
  std::vector<std::filesystem::path> tried;  ///< every location looked at, in order

  /// "not found (looked in: a, b, c)".
  std::string not_found_message() const;
};

/// Looks for the files in the documented order. InputError when `configured` is set but is
/// neither a file nor a folder holding one of `file_names`.
WeightSearch find_weights(const std::filesystem::path& configured, const std::vector<std::string>& file_names);

/// The repository's models/ folder (compiled in).
std::filesystem::path repository_models_dir();
/// <exe>/../share/pllvo/models when the running program is an installed one (the folder
/// exists), else empty.
std::filesystem::path installed_models_dir();
/// installed_models_dir() when set, else repository_models_dir().
std::filesystem::path default_models_dir();

}  // namespace pllvo::nn
