#include "pllvo/io/folder_sequence.h"

#include <algorithm>
#include <cctype>
#include <set>

#include "pllvo/common/error.h"
#include "pllvo/io/camera_yaml_source.h"
#include "pllvo/io/dataset_files.h"

namespace pllvo::io {

namespace fs = std::filesystem;

namespace {

bool is_image_file(const fs::path& p) {
  static const std::set<std::string> kExtensions = {".png", ".jpg", ".jpeg", ".pgm", ".ppm",
                                                    ".bmp", ".tif", ".tiff"};
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return kExtensions.count(ext) > 0;
}

std::vector<fs::path> images_sorted_by_name(const fs::path& dir) {
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.is_regular_file() && is_image_file(e.path())) files.push_back(e.path());
  std::sort(files.begin(), files.end(),
            [](const fs::path& a, const fs::path& b) { return a.filename() < b.filename(); });
  return files;
}

}  // namespace

FolderSequence::FolderSequence(const fs::path& root, const SequenceOptions& options) : Sequence(root) {
  if (!fs::is_directory(root)) throw InputError(root, "dataset folder not found");
  const auto cam = load_dataset_camera(root, options, "an image folder needs its camera's calibration");
  calib_.cam0 = cam.camera;

  if (fs::exists(root / "images.txt")) {
    const auto list = read_image_list(root / "images.txt", root);
    stamps_ = list.stamps;
    left_files_ = list.files;
  } else {
    const fs::path dir = fs::is_directory(root / "images") ? root / "images" : root;
    left_files_ = images_sorted_by_name(dir);
    if (left_files_.empty())
      throw InputError(dir, "no images found (png, jpg, jpeg, pgm, ppm, bmp, tif, tiff): empty sequence");
    if (!(cam.fps > 0))
      throw InputError(cam.file, std::string("fps"),
                       "missing: without images.txt the frames are timed by the camera YAML's fps");
    for (size_t i = 0; i < left_files_.size(); ++i) stamps_.push_back(static_cast<double>(i) / cam.fps);
  }
  calib_.rate_hz = cam.fps > 0 ? cam.fps : mean_rate(stamps_);
  // Depth images (RGB-D): depth/ holds one 16-bit PNG per image, of the same file name.
  if (options.depth && !options.mono && fs::is_directory(root / "depth")) {
    if (!(cam.depth_factor > 0))
      throw InputError(cam.file, std::string("depth_factor"),
                       "missing: the folder has depth/, whose 16-bit values need their units per metre");
    calib_.depth_factor = cam.depth_factor;
    for (const auto& image : left_files_) {
      const fs::path file = root / "depth" / image.filename().replace_extension(".png");
      if (!fs::is_regular_file(file)) throw InputError(file, "depth image of " + image.filename().string() + " not found");
      depth_files_.push_back(file);
    }
  }
  if (fs::exists(root / "groundtruth.txt")) ground_truth_ = read_tum(root / "groundtruth.txt");
}

}  // namespace pllvo::io
