#include "pllvo/io/tum_sequence.h"

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
  if (fs::exists(root / "groundtruth.txt")) ground_truth_ = read_tum(root / "groundtruth.txt");
}

}  // namespace pllvo::io
