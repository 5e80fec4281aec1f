#pragma once
// Helpers for the dataset reader tests: fixture paths, temporary (broken) dataset copies
// built from a few fixture files under the system temp folder, and InputError checks.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "pllvo/common/error.h"
#include "pllvo/common/fixtures.h"

namespace pllvo::io::testing {

namespace fs = std::filesystem;

inline fs::path data_path(const std::string& relative) { return pllvo::shared_path("data/" + relative); }

/// A fresh folder under the temp dir, removed again when the test ends.
class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = fs::temp_directory_path() /
            ("pllvo_io_" + std::string(info->test_suite_name()) + "_" + info->name() + "_" + std::to_string(::getpid()));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const fs::path& path() const { return path_; }
  fs::path operator/(const fs::path& p) const { return path_ / p; }

 private:
  fs::path path_;
};

inline void write_file(const fs::path& file, const std::string& text) {
  fs::create_directories(file.parent_path());
  std::ofstream(file) << text;
}

inline std::string read_file(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

inline std::vector<std::string> read_lines(const fs::path& file) {
  std::ifstream in(file);
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}

inline void write_lines(const fs::path& file, const std::vector<std::string>& lines) {
  std::string text;
  for (const auto& l : lines) text += l + "\n";
  write_file(file, text);
}

inline void copy_into(const fs::path& from, const fs::path& to) {
  fs::create_directories(to.parent_path());
  fs::copy_file(from, to, fs::copy_options::overwrite_existing);
}

/// A EuRoC copy with the first `frames` frames of each camera of the fixture (the csv header
/// and the first `frames` data lines), sensor.yaml and the ground truth. Returns the root.
inline fs::path make_euroc_copy(const fs::path& dir, size_t frames, bool stereo = true) {
  const fs::path src = data_path("euroc_V1_01_easy_micro/mav0");
  for (const std::string cam : {"cam0", "cam1"}) {
    if (cam == "cam1" && !stereo) break;
    const auto lines = read_lines(src / cam / "data.csv");
    std::vector<std::string> kept(lines.begin(), lines.begin() + 1 + frames);
    write_lines(dir / "mav0" / cam / "data.csv", kept);
    copy_into(src / cam / "sensor.yaml", dir / "mav0" / cam / "sensor.yaml");
    for (size_t i = 1; i < kept.size(); ++i) {
      const std::string name = kept[i].substr(kept[i].find(',') + 1);
      copy_into(src / cam / "data" / name, dir / "mav0" / cam / "data" / name);
    }
  }
  copy_into(src / "state_groundtruth_estimate0" / "data.csv", dir / "mav0" / "state_groundtruth_estimate0" / "data.csv");
  return dir;
}

/// Runs `fn`, expects an InputError and returns it (a default one after a test failure).
inline pllvo::InputError expect_input_error(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const pllvo::InputError& e) {
    return e;
  }
  ADD_FAILURE() << "expected an InputError";
  return pllvo::InputError("(none)");
}

inline double pixel_sum(const cv::Mat& image) { return cv::sum(image)[0]; }

}  // namespace pllvo::io::testing
