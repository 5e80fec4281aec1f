#pragma once
// Location of the shared fixtures (real data, test vectors, official weights).
#include <filesystem>

namespace pllvo {

/// `$PLLVO_SHARED` when set, else the CMake cache variable PLLVO_SHARED_DIR
/// (default: ../shared next to the repository).
std::filesystem::path shared_dir();

/// shared_dir()/relative; raises InputError naming the path and the variable when it
/// does not exist, so a test that needs a fixture fails clearly instead of skipping.
std::filesystem::path shared_path(const std::filesystem::path& relative);

}  // namespace pllvo
