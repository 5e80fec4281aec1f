#include "pllvo/io/tum_sequence.h"

#include <spdlog/spdlog.h>

#include "pllvo/common/error.h"
#include "pllvo/io/camera_yaml_source.h"
#include "pllvo/io/dataset_files.h"

namespace pllvo::io {

namespace fs = std::filesystem;

TumSequence::TumSequence(const fs::path& root, const SequenceOptions& options) : Sequence(root) {
  if (!fs::is_directory(root)) throw InputError(root, "dataset folder not found");
  const auto cam = load_dataset_camera(root, options, "TUM RGB-D ships no intrinsics");
  const auto list = read_image_list(root / "rgb.txt", root);
  calib_.cam0 = cam.camera;
  stamps_ = list.stamps;
  left_files_ = list.files;
  calib_.rate_hz = cam.fps > 0 ? cam.fps : mean_rate(stamps_);
  if (options.depth && !options.mono && fs::exists(root / "depth.txt")) {
    const auto depth = read_image_list(root / "depth.txt", root);
    calib_.depth_factor = cam.depth_factor > 0 ? cam.depth_factor : 5000.0;
    size_t missing = 0;
    for (const long j : nearest_in_time(stamps_, depth.stamps, options.depth_max_dt)) {
      depth_files_.push_back(j >= 0 ? depth.files[j] : fs::path());
      missing += j >= 0 ? 0 : 1;
    }
    if (missing)
      spdlog::warn("{}: {} of {} colour frames have no depth image within {} s; they are tracked without depth",
                   (root / "depth.txt").string(), missing, stamps_.size(), options.depth_max_dt);
  }
  if (fs::exists(root / "groundtruth.txt")) ground_truth_ = read_tum(root / "groundtruth.txt");
}

}  // namespace pllvo::io
