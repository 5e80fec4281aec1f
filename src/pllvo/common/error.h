#pragma once
// Errors that reach the user. Bad input is reported once, naming the file and the
// line (or YAML key) at fault, so the CLI can print it and exit non-zero.
#include <filesystem>
#include <stdexcept>
#include <string>

namespace pllvo {

/// Bad user input: missing/malformed file, wrong image size, NaN, empty sequence...
/// `where()` is "file:line" or "file: key" (empty when not tied to a file).
class InputError : public std::runtime_error {
 public:
  InputError(const std::string& message);
  InputError(const std::filesystem::path& file, const std::string& message);
  InputError(const std::filesystem::path& file, long line, const std::string& message);
  InputError(const std::filesystem::path& file, const std::string& key, const std::string& message);

  const std::string& file() const { return file_; }
  long line() const { return line_; }  ///< 1-based, 0 when unknown
  const std::string& key() const { return key_; }

 private:
  std::string file_;
  long line_ = 0;
  std::string key_;
};

/// A failure inside pllvo that is not the user's input (a broken invariant).
class InternalError : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

}  // namespace pllvo
