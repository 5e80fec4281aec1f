#pragma once
// SuperPoint on keyframes (paper 3.2): the network once per keyframe at a reduced input
// scale, the adaptive score threshold (nn::AdaptiveThreshold: keypoint count and grid
// coverage, corrected by how well the previous keyframe matched), new points kept away from
// tracked ones and spread over a grid, tracked points described where they are from the same
// dense descriptor map. Descriptors are float rows (CV_32F, unit norm), matched by LightGlue
// or mutual nearest neighbours.
#include <filesystem>
#include <mutex>
#include <memory>
#include <optional>

#include "pllvo/nn/adaptive_threshold.h"
#include "pllvo/nn/superpoint.h"
#include "pllvo/vo/point_frontend.h"

namespace pllvo::vo {

class SuperPointFrontend final : public PointFrontend {
 public:
  /// Loads the weights (frontend.superpoint_weights, else the nn lookup); InputError saying
  /// where it looked when there are none.
  explicit SuperPointFrontend(const FrontendConfig& config);
  std::string name() const override { return "superpoint"; }
  PointFeatures detect(const cv::Mat& image, const std::vector<cv::Point2f>& tracked) override;
  void report_matches(int matched, int keypoints) override;

  const std::filesystem::path& weights_file() const { return superpoint_.weights_file(); }

 private:
  FrontendConfig config_;
  nn::SuperPoint superpoint_;
  std::mutex threshold_mutex_;  ///< guards threshold_
  nn::AdaptiveThreshold threshold_;
};

/// The SuperPoint weights the front end would load (nn lookup order), or nullopt when none
/// are found; InputError when an explicitly configured path does not exist.
std::optional<std::filesystem::path> find_superpoint_weights(const FrontendConfig& config);

}  // namespace pllvo::vo
