#include "pllvo/nn/model_files.h"

#include <cstdlib>

#include "pllvo/common/error.h"

#ifndef PLLVO_REPO_MODELS_DIR
#define PLLVO_REPO_MODELS_DIR "models"
#endif

namespace pllvo::nn {

std::vector<std::string> superpoint_weight_names() { return {kSuperPointWeights, kPllvoSuperPointWeights}; }
std::vector<std::string> lightglue_weight_names() { return {kLightGlueWeights, kPllvoLightGlueWeights}; }

std::string WeightSearch::not_found_message() const {
  std::string s = "not found (looked in:";
  for (std::size_t i = 0; i < tried.size(); ++i) s += (i ? ", " : " ") + tried[i].string();
  return s + ")";
}

std::filesystem::path repository_models_dir() { return PLLVO_REPO_MODELS_DIR; }

std::filesystem::path installed_models_dir() {
  std::error_code ec;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) return {};
  const auto dir = exe.parent_path().parent_path() / "share" / "pllvo" / "models";
  return std::filesystem::is_directory(dir, ec) ? dir : std::filesystem::path();
}

std::filesystem::path default_models_dir() {
  const auto installed = installed_models_dir();
  return installed.empty() ? repository_models_dir() : installed;
}

namespace {

WeightSearch search_folder(const std::filesystem::path& folder, const std::vector<std::string>& file_names) {
  WeightSearch search;
  for (const auto& name : file_names) {
    const auto p = folder / name;
    search.tried.push_back(p);
    if (std::filesystem::is_regular_file(p)) {
      search.found = p;
      break;
    }
  }
  return search;
}

}  // namespace

WeightSearch find_weights(const std::filesystem::path& configured, const std::vector<std::string>& file_names) {
  namespace fs = std::filesystem;
  if (!configured.empty()) {
    if (fs::is_directory(configured)) {
      auto search = search_folder(configured, file_names);
      if (!search.found) throw InputError(configured, "no weights file in this folder (configured path): " +
                                                          search.not_found_message());
      return search;
    }
    if (!fs::is_regular_file(configured)) throw InputError(configured, "weights file not found (configured path)");
    WeightSearch search;
    search.tried.push_back(configured);
    search.found = configured;
    return search;
  }
  const char* env = std::getenv("PLLVO_MODELS");
  return search_folder(env && *env ? fs::path(env) : default_models_dir(), file_names);
}

}  // namespace pllvo::nn
