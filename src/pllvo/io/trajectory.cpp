#include "pllvo/io/trajectory.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <string_view>

#include "pllvo/common/error.h"

namespace pllvo::io {

namespace fs = std::filesystem;

namespace {

/// Splits like Python's csv module with a one-character delimiter and no quoting:
/// consecutive delimiters give empty fields (which then fail to parse, as in evo).
std::vector<std::string_view> split(std::string_view line, char delim) {
  std::vector<std::string_view> out;
  size_t start = 0;
  while (true) {
    const size_t pos = line.find(delim, start);
    out.push_back(line.substr(start, pos == std::string_view::npos ? std::string_view::npos : pos - start));
    if (pos == std::string_view::npos) break;
    start = pos + 1;
  }
  return out;
}

std::string_view trim(std::string_view s) {
  const auto ws = " \t\r\n";
  const size_t b = s.find_first_not_of(ws);
  if (b == std::string_view::npos) return {};
  return s.substr(b, s.find_last_not_of(ws) - b + 1);
}

double parse_number(std::string_view field, const fs::path& file, long line) {
  const auto s = trim(field);
  double v = 0;
  const char* first = s.data();
  if (!s.empty() && s.front() == '+') ++first;
  const auto [ptr, ec] = std::from_chars(first, s.data() + s.size(), v);
  if (s.empty() || ec != std::errc() || ptr != s.data() + s.size())
    throw InputError(file, line, "'" + std::string(field) + "' is not a number");
  if (!std::isfinite(v)) throw InputError(file, line, "non-finite value '" + std::string(field) + "'");
  return v;
}

struct Row {
  long line;
  std::vector<double> values;
};

/// Reads every non-comment line (lines starting with '#'); blank lines are skipped.
std::vector<Row> read_rows(const fs::path& file, char delim, size_t min_cols, size_t max_cols,
                           const char* layout) {
  std::ifstream in(file);
  if (!in) throw InputError(file, fs::exists(file) ? "cannot open" : "file not found");
  std::vector<Row> rows;
  std::string text;
  long line = 0;
  while (std::getline(in, text)) {
    ++line;
    if (!text.empty() && text.back() == '\r') text.pop_back();
    if (text.rfind('#', 0) == 0 || trim(text).empty()) continue;
    const auto fields = split(text, delim);
    if (fields.size() < min_cols || fields.size() > max_cols)
      throw InputError(file, line, "expected " + std::string(layout) + ", found " +
                                       std::to_string(fields.size()) + " fields");
    Row row{line, {}};
    for (const auto& f : fields) row.values.push_back(parse_number(f, file, line));
    rows.push_back(std::move(row));
  }
  if (rows.empty()) throw InputError(file, "no poses in file");
  return rows;
}

void check_stamps_increasing(const Trajectory& traj, const std::vector<Row>& rows,
                             const fs::path& file) {
  for (size_t i = 1; i < traj.stamps.size(); ++i)
    if (traj.stamps[i] < traj.stamps[i - 1])
      throw InputError(file, rows[i].line, "timestamp goes backwards");
}

Eigen::Isometry3d pose_from(const Eigen::Vector3d& t, const Eigen::Matrix3d& R) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R;
  T.translation() = t;
  return T;
}

std::FILE* open_for_writing(const fs::path& file) {
  if (file.has_parent_path()) fs::create_directories(file.parent_path());
  std::FILE* f = std::fopen(file.c_str(), "w");
  if (!f) throw InputError(file, "cannot write");
  return f;
}

}  // namespace

Eigen::Matrix3d rotation_from_quaternion(double qw, double qx, double qy, double qz) {
  // Same arithmetic as evo's transformations.quaternion_matrix: normalise via
  // q *= sqrt(2/n), then the outer-product formula (non-unit and negated q are fine).
  double q[4] = {qw, qx, qy, qz};
  const double n = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
  if (n < 4.0 * std::numeric_limits<double>::epsilon()) return Eigen::Matrix3d::Identity();
  const double s = std::sqrt(2.0 / n);
  for (double& v : q) v *= s;
  auto o = [&](int i, int j) { return q[i] * q[j]; };
  Eigen::Matrix3d R;
  R << 1.0 - o(2, 2) - o(3, 3), o(1, 2) - o(3, 0), o(1, 3) + o(2, 0),  //
      o(1, 2) + o(3, 0), 1.0 - o(1, 1) - o(3, 3), o(2, 3) - o(1, 0),   //
      o(1, 3) - o(2, 0), o(2, 3) + o(1, 0), 1.0 - o(1, 1) - o(2, 2);
  return R;
}

Trajectory read_tum(const fs::path& file) {
  const auto rows = read_rows(file, ' ', 8, 8, "8 single-space separated numbers 't tx ty tz qx qy qz qw'");
  Trajectory traj;
  for (const auto& r : rows) {
    const auto& v = r.values;
    traj.push_back(v[0], pose_from({v[1], v[2], v[3]}, rotation_from_quaternion(v[7], v[4], v[5], v[6])));
  }
  check_stamps_increasing(traj, rows, file);
  return traj;
}

Trajectory read_euroc_csv(const fs::path& file, const Eigen::Isometry3d* T_body_cam) {
  const auto rows = read_rows(file, ',', 8, 1000, "at least 8 comma-separated columns 'ns, px, py, pz, qw, qx, qy, qz, ...'");
  Trajectory traj;
  for (const auto& r : rows) {
    const auto& v = r.values;
    Eigen::Isometry3d T = pose_from({v[1], v[2], v[3]}, rotation_from_quaternion(v[4], v[5], v[6], v[7]));
    if (T_body_cam) T = T * *T_body_cam;
    traj.push_back(v[0] / 1e9, T);
  }
  check_stamps_increasing(traj, rows, file);
  return traj;
}

Trajectory read_kitti(const fs::path& file) {
  const auto rows = read_rows(file, ' ', 12, 12, "12 single-space separated numbers (row-major 3x4 [R|t])");
  Trajectory traj;
  for (const auto& r : rows) {
    const auto& v = r.values;
    Eigen::Matrix3d R;
    R << v[0], v[1], v[2], v[4], v[5], v[6], v[8], v[9], v[10];
    traj.poses.push_back(pose_from({v[3], v[7], v[11]}, R));
  }
  return traj;
}

Trajectory read_trajectory(const fs::path& file) {
  std::ifstream in(file);
  if (!in) throw InputError(file, fs::exists(file) ? "cannot open" : "file not found");
  std::string text;
  while (std::getline(in, text)) {
    if (text.rfind('#', 0) == 0 || trim(text).empty()) continue;
    if (text.find(',') != std::string::npos) return read_euroc_csv(file);
    if (split(trim(text), ' ').size() == 12) return read_kitti(file);
    return read_tum(file);
  }
  throw InputError(file, "no poses in file");
}

void write_tum(const Trajectory& traj, const fs::path& file) {
  if (!traj.has_stamps() && !traj.empty())
    throw InternalError("write_tum: trajectory without timestamps");
  std::FILE* f = open_for_writing(file);
  std::fprintf(f, "# timestamp tx ty tz qx qy qz qw\n");
  for (size_t i = 0; i < traj.size(); ++i) {
    const auto& T = traj.poses[i];
    const Eigen::Quaterniond q(T.linear());
    const auto& t = T.translation();
    std::fprintf(f, "%.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g\n", traj.stamps[i], t.x(), t.y(),
                 t.z(), q.x(), q.y(), q.z(), q.w());
  }
  if (std::fclose(f) != 0) throw InputError(file, "write failed");
}

void write_kitti(const Trajectory& traj, const fs::path& file) {
  std::FILE* f = open_for_writing(file);
  for (const auto& T : traj.poses) {
    const auto M = T.matrix();
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) std::fprintf(f, (r == 2 && c == 3) ? "%.17g\n" : "%.17g ", M(r, c));
  }
  if (std::fclose(f) != 0) throw InputError(file, "write failed");
}

}  // namespace pllvo::io
