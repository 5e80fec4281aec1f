#include "pllvo/common/error.h"

namespace pllvo {

InputError::InputError(const std::string& message) : std::runtime_error(message) {}

InputError::InputError(const std::filesystem::path& file, const std::string& message)
    : std::runtime_error(file.string() + ": " + message), file_(file.string()) {}

InputError::InputError(const std::filesystem::path& file, long line, const std::string& message)
    : std::runtime_error(file.string() + ":" + std::to_string(line) + ": " + message),
      file_(file.string()),
      line_(line) {}

InputError::InputError(const std::filesystem::path& file, const std::string& key,
                       const std::string& message)
    : std::runtime_error(file.string() + ": key '" + key + "': " + message),
      file_(file.string()),
      key_(key) {}

}  // namespace pllvo
