#include "pllvo/nn/model_files.h"

#include <cstdlib>

#include "pllvo/common/error.h"

#ifndef PLLVO_REPO_MODELS_DIR
#define PLLVO_REPO_MODELS_DIR "models"
#endif

namespace pllvo::nn {

std::string WeightSearch::not_found_message(const std::string& file_name) const {
  std::string s = "'" + file_name + "' not found (looked in:";
  for (std::size_t i = 0; i < tried.size(); ++i) s += (i ? ", " : " ") + tried[i].string();
  return s + ")";
}

std::filesystem::path repository_models_dir() { return PLLVO_REPO_MODELS_DIR; }

WeightSearch find_weights(const std::filesystem::path& configured, const std::string& file_name) {
  namespace fs = std::filesystem;
  WeightSearch search;
  if (!configured.empty()) {
    const fs::path p = fs::is_directory(configured) ? configured / file_name : configured;
    search.tried.push_back(p);
    if (!fs::is_regular_file(p)) throw InputError(p, "weights file not found (configured path)");
    search.found = p;
    return search;
  }
  std::vector<fs::path> candidates;
  if (const char* env = std::getenv("PLLVO_MODELS"); env && *env) candidates.push_back(fs::path(env) / file_name);
  candidates.push_back(repository_models_dir() / file_name);
  for (const auto& p : candidates) {
    search.tried.push_back(p);
    if (fs::is_regular_file(p)) {
      search.found = p;
      break;
    }
  }
  return search;
}

}  // namespace pllvo::nn
