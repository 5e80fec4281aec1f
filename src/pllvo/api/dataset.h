#pragma once
// pllvo's library API: a dataset folder's frames, for programs that feed pllvo::Odometry from
// recorded data (EuRoC ASL, KITTI odometry, TUM RGB-D, image folder with camera.yaml).
#include <filesystem>
#include <memory>
#include <vector>

#include <opencv2/core.hpp>

#include "pllvo/api/calibration.h"
#include "pllvo/api/odometry.h"

namespace pllvo {

namespace io {
class Sequence;
}

struct DatasetFrame {
  double timestamp = 0;
  cv::Mat left;   ///< 8-bit gray
  cv::Mat right;  ///< empty for a monocular dataset (or mono = true)
  cv::Mat depth;  ///< CV_32FC1 metres (0: no depth at the pixel); empty without depth images
};

class Dataset {
 public:
  /// InputError naming the file and line for anything missing or malformed.
  explicit Dataset(const std::filesystem::path& folder, bool mono = false);
  ~Dataset();
  Dataset(Dataset&&) noexcept;
  Dataset& operator=(Dataset&&) noexcept;

  size_t size() const;
  /// Loads frame i; InputError naming the image file when it is unreadable.
  DatasetFrame frame(size_t i) const;
  const Calibration& calibration() const { return calibration_; }
  /// T_world_cam0 per stamped pose; empty when the dataset has none.
  std::vector<StampedPose> ground_truth() const;
  const io::Sequence& internal() const { return *sequence_; }

 private:
  std::unique_ptr<io::Sequence> sequence_;
  Calibration calibration_;
};

}  // namespace pllvo
