// pllvo calibrate INPUT --board ... --out camera.yaml: camera calibration from views of a board.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <memory>

#include <opencv2/imgcodecs.hpp>

#include "commands.h"
#include "pllvo/camera/board_calibration.h"
#include "pllvo/camera/camera_yaml.h"
#include "pllvo/common/error.h"
#include "pllvo/io/calibration_file.h"
#include "pllvo/io/video_source.h"

namespace pllvo::cli {
namespace {

namespace fs = std::filesystem;
using Images = std::vector<std::pair<std::string, cv::Mat>>;

struct CalibrateArgs {
  std::string input, right, out, model = "radtan", stereo_layout = "mono";
  camera::BoardSpec board;
  size_t every = 10;
  size_t max_views = 60;
  size_t min_views = 6;
};

bool is_image(const fs::path& p) {
  std::string e = p.extension().string();
  std::transform(e.begin(), e.end(), e.begin(), ::tolower);
  for (const char* x : {".png", ".jpg", ".jpeg", ".pgm", ".ppm", ".bmp", ".tif", ".tiff"})
    if (e == x) return true;
  return false;
}

/// A folder's images (sorted by name), or every `every`-th frame of a video source, split when side by side.
std::pair<Images, Images> read_views(const std::string& input, const CalibrateArgs& a) {
  Images left, right;
  if (fs::is_directory(input)) {
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(input))
      if (e.is_regular_file() && is_image(e.path())) files.push_back(e.path());
    std::sort(files.begin(), files.end());
    if (files.empty()) throw InputError(input, "no images in this folder");
    for (const auto& f : files) left.emplace_back(f.string(), cv::imread(f.string(), cv::IMREAD_GRAYSCALE));
    return {left, right};
  }
  io::VideoSourceOptions options;
  options.stereo_layout = a.stereo_layout;
  const auto source = io::VideoSource::open(input, options);
  io::Frame frame;
  size_t k = 0;
  while (left.size() < a.max_views && source->next(frame) == io::VideoSource::Status::kFrame) {
    if (k++ % a.every != 0) continue;
    const std::string name = input + ": frame " + std::to_string(frame.index);
    left.emplace_back(name, frame.left.clone());
    if (!frame.right.empty()) right.emplace_back(name + " (right)", frame.right.clone());
  }
  return {left, right};
}

void print_views(const char* which, const camera::BoardCalibration& c) {
  size_t found = 0;
  for (const auto& v : c.views) found += v.found ? 1 : 0;
  std::printf("%s: board found in %zu of %zu images, RMS reprojection error %.3f px\n", which, found, c.views.size(),
              c.rms_px);
  for (const auto& v : c.views)
    if (v.found)
      std::printf("  %-48s %3d corners  %.3f px\n", v.name.c_str(), v.corners, v.rms_px);
    else
      std::printf("  %-48s board not found\n", v.name.c_str());
  const auto& k = c.camera->intrinsics();
  std::printf("  fx %.3f  fy %.3f  cx %.3f  cy %.3f  distortion (%s)", k.fx, k.fy, k.cx, k.cy, c.camera->name().c_str());
  for (double d : c.camera->distortion()) std::printf(" %.6f", d);
  std::printf("\n");
}

/// Written to a temporary name and renamed: never half-written.
void write_file(const fs::path& out, const std::function<void(const fs::path&)>& write) {
  if (out.has_parent_path()) fs::create_directories(out.parent_path());
  const fs::path tmp = out.string() + ".tmp";
  write(tmp);
  fs::rename(tmp, out);
}

void calibrate(const CalibrateArgs& a) {
  camera::CalibrationOptions options;
  options.model = a.model;
  options.min_views = a.min_views;
  auto [left, right] = read_views(a.input, a);
  if (!a.right.empty()) right = read_views(a.right, a).first;
  if (right.empty()) {
    const auto c = camera::calibrate_camera(left, a.board, options);
    print_views("camera", c);
    write_file(a.out, [&](const fs::path& p) { camera::save_camera_yaml(*c.camera, p); });
    std::printf("camera YAML: %s\n", a.out.c_str());
    return;
  }
  const auto s = camera::calibrate_stereo(left, right, a.board, options);
  print_views("left", s.left);
  print_views("right", s.right);
  const Eigen::Vector3d t = s.T_left_right.translation();
  std::printf("stereo: %zu pairs, RMS %.3f px, baseline %.4f m (right camera at %.4f %.4f %.4f in the left's frame)\n",
              s.pairs, s.rms_px, t.norm(), t.x(), t.y(), t.z());
  write_file(a.out, [&](const fs::path& p) {
    io::save_kalibr_camchain(*s.left.camera, s.right.camera.get(), s.T_left_right, p);
  });
  std::printf("Kalibr camchain (stereo): %s\n", a.out.c_str());
}

}  // namespace

void add_calibrate_command(CLI::App& app) {
  auto a = std::make_shared<CalibrateArgs>();
  auto* cmd = app.add_subcommand("calibrate", "camera calibration from images of a chessboard or ChArUco board");
  cmd->footer("Writes pllvo's camera YAML (one camera) or a Kalibr camchain (a stereo pair), both read by `pllvo run "
              "--camera`. Example: pllvo calibrate shots/ --board chessboard --rows 7 --cols 10 --square 0.025 --out "
              "camera.yaml");
  cmd->add_option("input", a->input, "a folder of images, or a video source (file, camera index, /dev/videoN)")
      ->required();
  cmd->add_option("--right", a->right, "the right camera's images (same order as the left's): stereo calibration");
  cmd->add_option("--board", a->board.type, "chessboard | charuco")->check(CLI::IsMember({"chessboard", "charuco"}));
  cmd->add_option("--rows", a->board.rows, "squares per column of the board")->required();
  cmd->add_option("--cols", a->board.cols, "squares per row of the board")->required();
  cmd->add_option("--square", a->board.square_m, "side of a square, metres")->required()->check(CLI::PositiveNumber);
  cmd->add_option("--marker", a->board.marker_m, "ChArUco: side of a marker, metres (default 0.7 x square)");
  cmd->add_option("--dictionary", a->board.dictionary, "ChArUco: OpenCV's predefined ArUco dictionary number (0: 4x4_50)");
  cmd->add_option("--model", a->model, "radtan | equidistant (fisheye)")->check(CLI::IsMember({"radtan", "equidistant"}));
  cmd->add_option("--stereo-layout", a->stereo_layout, "video source: mono, or side-by-side stereo")
      ->check(CLI::IsMember({"mono", "side-by-side"}));
  cmd->add_option("--every", a->every, "video source: use every N-th frame (default 10)")->check(CLI::PositiveNumber);
  cmd->add_option("--min-views", a->min_views, "refuse with fewer views showing the board (default 6)");
  cmd->add_option("--out", a->out, "the calibration file to write")->required();
  cmd->callback([a] { calibrate(*a); });
}

}  // namespace pllvo::cli
