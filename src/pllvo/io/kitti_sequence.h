#pragma once
// KITTI odometry layout:
//   sequences/XX/image_0/%06d.png   left gray camera (image_1/: right, optional)
//   sequences/XX/calib.txt          `P0: 12 numbers` ... (rectified 3x4 projection matrices)
//   sequences/XX/times.txt          one timestamp (s) per frame
//   poses/XX.txt                    ground truth, 12 numbers per frame (T_world_cam0, optional)
#include <filesystem>
#include <optional>

#include "pllvo/camera/camera_model.h"
#include "pllvo/io/sequence.h"

namespace pllvo::io {

/// The two gray cameras of calib.txt. The images are rectified, so the cameras are pinholes
/// without distortion, and cam1 sits at +baseline along cam0's x axis.
struct KittiCalibration {
  camera::PinholeIntrinsics cam0;                ///< from P0
  std::optional<camera::PinholeIntrinsics> cam1;  ///< from P1, when the file has it
  double baseline = 0;                           ///< metres, P0[0,3]/fx0 - P1[0,3]/fx1; 0 without P1
};
/// Reads the `P0:` and `P1:` lines (other keys such as P2, P3, Tr are ignored). InputError
/// naming the file and line (or the key, when P0 is missing).
KittiCalibration read_kitti_calib(const std::filesystem::path& file);

/// `root`: a sequence folder (sequences/XX) or the KITTI root holding sequences/ with exactly
/// one sequence. Stereo when image_1/ exists and options.mono is not set. The image size is
/// read from the first image (calib.txt has none). Ground truth from ../../poses/XX.txt when it
/// exists: one pose per frame, stamped with times.txt.
class KittiSequence final : public Sequence {
 public:
  KittiSequence(const std::filesystem::path& root, const SequenceOptions& options = {});
  std::string format() const override { return "kitti"; }
};

}  // namespace pllvo::io
