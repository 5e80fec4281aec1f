#include "pllvo/common/fixtures.h"

#include <cstdlib>

#include "pllvo/common/error.h"

#ifndef PLLVO_SHARED_DIR
#define PLLVO_SHARED_DIR "../shared"
#endif

namespace pllvo {

std::filesystem::path shared_dir() {
  if (const char* env = std::getenv("PLLVO_SHARED"); env && *env) return env;
  return PLLVO_SHARED_DIR;
}

std::filesystem::path shared_path(const std::filesystem::path& relative) {
  const auto p = shared_dir() / relative;
  if (!std::filesystem::exists(p))
    throw InputError(p, "shared fixture missing (set PLLVO_SHARED or the CMake variable "
                        "PLLVO_SHARED_DIR to the folder holding data/, testvectors/, models/)");
  return p;
}

}  // namespace pllvo
