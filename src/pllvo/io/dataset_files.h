#pragma once
// Reading the small text files datasets ship (image lists, timestamps, csv indexes), with
// every error naming the file and the line at fault.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace pllvo::io {

/// One data line of a text table: its 1-based line number and its fields (trimmed).
struct TextRow {
  long line = 0;
  std::vector<std::string> fields;
};

enum class Separator {
  kComma,      ///< csv: every comma separates (empty fields are kept, and then rejected)
  kWhitespace  ///< runs of spaces and tabs separate
};

/// Every line that is neither blank nor a comment (first non-blank character '#').
/// InputError when the file is missing or unreadable.
std::vector<TextRow> read_text_rows(const std::filesystem::path& file, Separator separator);

/// Parses a whole field as a finite number; InputError(file, line) naming `what` otherwise.
double parse_double(const std::string& field, const std::filesystem::path& file, long line,
                    const std::string& what);
int64_t parse_int64(const std::string& field, const std::filesystem::path& file, long line,
                    const std::string& what);

/// Raises InputError(file, line of the offender) unless `values` increase strictly.
/// `lines[i]` is the line that gave `values[i]`.
template <typename T>
void require_strictly_increasing(const std::vector<T>& values, const std::vector<long>& lines,
                                 const std::filesystem::path& file);

/// A list of `timestamp path` lines (TUM's rgb.txt, an image folder's images.txt): stamps in
/// seconds, paths relative to `base` unless absolute. Checks that every image file exists,
/// that stamps increase strictly and that the list is not empty.
struct ImageList {
  std::vector<double> stamps;
  std::vector<std::filesystem::path> files;
};
ImageList read_image_list(const std::filesystem::path& file, const std::filesystem::path& base);

/// For each stamp of `t0`, the index of the nearest stamp of `t1` when they are at most `max_dt`
/// apart, else -1. Both increasing (one sweep; the later index on ties).
template <typename T>
std::vector<long> nearest_in_time(const std::vector<T>& t0, const std::vector<T>& t1, T max_dt);

/// Mean frame rate of strictly increasing stamps (Hz); 0 for fewer than two.
double mean_rate(const std::vector<double>& stamps);

}  // namespace pllvo::io
