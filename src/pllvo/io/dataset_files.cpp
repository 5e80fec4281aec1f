#include "pllvo/io/dataset_files.h"

#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

#include "pllvo/common/error.h"

namespace pllvo::io {

namespace fs = std::filesystem;

namespace {

std::string trim(const std::string& s) {
  const auto ws = " \t\r\n";
  const size_t b = s.find_first_not_of(ws);
  if (b == std::string::npos) return {};
  return s.substr(b, s.find_last_not_of(ws) - b + 1);
}

std::vector<std::string> split(const std::string& text, Separator separator) {
  std::vector<std::string> out;
  if (separator == Separator::kWhitespace) {
    std::istringstream in(text);
    for (std::string f; in >> f;) out.push_back(f);
    return out;
  }
  size_t start = 0;
  while (true) {
    const size_t pos = text.find(',', start);
    out.push_back(trim(text.substr(start, pos == std::string::npos ? std::string::npos : pos - start)));
    if (pos == std::string::npos) return out;
    start = pos + 1;
  }
}

template <typename T>
std::string to_text(T v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}

}  // namespace

std::vector<TextRow> read_text_rows(const fs::path& file, Separator separator) {
  if (fs::is_directory(file)) throw InputError(file, "is a folder, expected a text file");
  std::ifstream in(file);
  if (!in) throw InputError(file, fs::exists(file) ? "cannot open" : "file not found");
  std::vector<TextRow> rows;
  std::string text;
  long line = 0;
  while (std::getline(in, text)) {
    ++line;
    const std::string t = trim(text);
    if (t.empty() || t.front() == '#') continue;
    rows.push_back({line, split(t, separator)});
  }
  if (in.bad()) throw InputError(file, line + 1, "read error");
  return rows;
}

double parse_double(const std::string& field, const fs::path& file, long line, const std::string& what) {
  double v = 0;
  const char* first = field.data();
  const char* last = field.data() + field.size();
  if (first != last && *first == '+') ++first;
  const auto [ptr, ec] = std::from_chars(first, last, v);
  if (field.empty() || ec != std::errc() || ptr != last)
    throw InputError(file, line, "'" + field + "' is not a number (expected " + what + ")");
  if (!std::isfinite(v)) throw InputError(file, line, "non-finite " + what + " '" + field + "'");
  return v;
}

int64_t parse_int64(const std::string& field, const fs::path& file, long line, const std::string& what) {
  int64_t v = 0;
  const auto [ptr, ec] = std::from_chars(field.data(), field.data() + field.size(), v);
  if (field.empty() || ec != std::errc() || ptr != field.data() + field.size())
    throw InputError(file, line, "'" + field + "' is not an integer (expected " + what + ")");
  return v;
}

template <typename T>
void require_strictly_increasing(const std::vector<T>& values, const std::vector<long>& lines,
                                 const fs::path& file) {
  for (size_t i = 1; i < values.size(); ++i)
    if (!(values[i] > values[i - 1]))
      throw InputError(file, lines.at(i),
                       "timestamp " + to_text(values[i]) + " is not after the previous one (" +
                           to_text(values[i - 1]) + ", line " + std::to_string(lines.at(i - 1)) +
                           "): timestamps must increase strictly");
}
template void require_strictly_increasing(const std::vector<double>&, const std::vector<long>&,
                                          const fs::path&);
template void require_strictly_increasing(const std::vector<int64_t>&, const std::vector<long>&,
                                          const fs::path&);

template <typename T>
std::vector<long> nearest_in_time(const std::vector<T>& t0, const std::vector<T>& t1, T max_dt) {
  const auto distance = [](T a, T b) { return a > b ? a - b : b - a; };
  std::vector<long> match(t0.size(), -1);
  if (t1.empty()) return match;
  size_t j = 0;
  for (size_t i = 0; i < t0.size(); ++i) {
    while (j + 1 < t1.size() && distance(t1[j + 1], t0[i]) <= distance(t1[j], t0[i])) ++j;
    if (distance(t1[j], t0[i]) <= max_dt) match[i] = static_cast<long>(j);
  }
  return match;
}
template std::vector<long> nearest_in_time(const std::vector<double>&, const std::vector<double>&, double);
template std::vector<long> nearest_in_time(const std::vector<int64_t>&, const std::vector<int64_t>&, int64_t);

ImageList read_image_list(const fs::path& file, const fs::path& base) {
  const auto rows = read_text_rows(file, Separator::kWhitespace);
  if (rows.empty()) throw InputError(file, "no frames listed (empty sequence; expected 'timestamp path' lines)");
  ImageList list;
  std::vector<long> lines;
  for (const auto& row : rows) {
    if (row.fields.size() != 2)
      throw InputError(file, row.line, "expected 'timestamp path', found " +
                                           std::to_string(row.fields.size()) + " fields");
    list.stamps.push_back(parse_double(row.fields[0], file, row.line, "a timestamp in seconds"));
    const fs::path image = fs::path(row.fields[1]).is_absolute() ? fs::path(row.fields[1]) : base / row.fields[1];
    if (!fs::is_regular_file(image))
      throw InputError(file, row.line, "image file not found: " + image.string());
    list.files.push_back(image);
    lines.push_back(row.line);
  }
  require_strictly_increasing(list.stamps, lines, file);
  return list;
}

double mean_rate(const std::vector<double>& stamps) {
  if (stamps.size() < 2) return 0.0;
  return static_cast<double>(stamps.size() - 1) / (stamps.back() - stamps.front());
}

}  // namespace pllvo::io
