#include "pllvo/io/sequence.h"

#include <stdexcept>

#include "pllvo/common/error.h"
#include "pllvo/io/euroc_sequence.h"
#include "pllvo/io/folder_sequence.h"
#include "pllvo/io/gray_image.h"
#include "pllvo/io/kitti_sequence.h"
#include "pllvo/io/tum_sequence.h"

namespace pllvo::io {

namespace fs = std::filesystem;

double Calibration::baseline() const {
  if (!stereo()) return 0.0;
  return (T_body_cam0.inverse() * T_body_cam1).translation().norm();
}

fs::path Sequence::image_path(size_t i, int cam) const {
  const auto& files = cam == 0 ? left_files_ : right_files_;
  if (i >= size()) throw std::out_of_range("frame index " + std::to_string(i) + " out of range");
  return i < files.size() ? files[i] : fs::path();
}

Frame Sequence::frame(size_t i) const {
  if (i >= size())
    throw std::out_of_range("frame " + std::to_string(i) + " of a sequence of " + std::to_string(size()));
  if (left_files_.size() != size() || (calib_.stereo() && right_files_.size() != size()))
    throw InternalError("Sequence::frame: a sequence that is not file-backed must override frame()");
  Frame f;
  f.index = i;
  f.timestamp = stamps_[i];
  const auto size_of = [](const camera::CameraPtr& cam) { return cv::Size(cam->width(), cam->height()); };
  f.left = read_gray_image(left_files_[i], size_of(calib_.cam0));
  if (calib_.stereo()) f.right = read_gray_image(right_files_[i], size_of(calib_.cam1));
  if (calib_.has_depth() && i < depth_files_.size() && !depth_files_[i].empty())
    f.depth = read_depth_image(depth_files_[i], calib_.depth_factor, size_of(calib_.cam0));
  return f;
}

std::string detect_format(const fs::path& root) {
  if (!fs::exists(root)) throw InputError(root, "dataset folder not found");
  if (!fs::is_directory(root)) throw InputError(root, "not a folder (expected a dataset folder)");
  // Each test looks for the folder or file that names its layout, so that a dataset with a
  // missing piece is still recognised and the error names that piece.
  if (fs::is_directory(root / "mav0") || fs::exists(root / "cam0" / "data.csv")) return "euroc";
  if (fs::exists(root / "times.txt") || fs::is_directory(root / "image_0") ||
      fs::is_directory(root / "sequences"))
    return "kitti";
  if (fs::exists(root / "rgb.txt")) return "tum";
  if (fs::exists(root / "images.txt") || fs::is_directory(root / "images") || fs::exists(root / "camera.yaml"))
    return "folder";
  throw InputError(root,
                   "cannot tell the dataset format: expected mav0/ (EuRoC), times.txt or sequences/ "
                   "(KITTI), rgb.txt (TUM RGB-D), or images.txt, images/ or camera.yaml (image folder)");
}

std::unique_ptr<Sequence> open_sequence(const fs::path& root, const SequenceOptions& options) {
  const std::string format = options.format == "auto" ? detect_format(root) : options.format;
  if (format != "euroc" && format != "tum" && format != "kitti" && format != "folder")
    throw InputError("unknown dataset format '" + format + "' (expected auto, euroc, tum, kitti or folder)");
  if (!fs::exists(root)) throw InputError(root, "dataset folder not found");
  if (!fs::is_directory(root)) throw InputError(root, "not a folder (expected a dataset folder)");
  if (format == "euroc") return std::make_unique<EurocSequence>(root, options);
  if (format == "tum") return std::make_unique<TumSequence>(root, options);
  if (format == "kitti") return std::make_unique<KittiSequence>(root, options);
  return std::make_unique<FolderSequence>(root, options);
}

}  // namespace pllvo::io
