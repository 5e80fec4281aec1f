#include "pllvo/vo/classical_frontends.h"

#include <opencv2/imgproc.hpp>

#include "pllvo/common/error.h"

namespace pllvo::vo {
namespace {

// ORB's descriptor needs a 31x31 patch (plus its edge threshold) around every point.
constexpr int kOrbPatch = 31;

cv::Mat checked_gray(const cv::Mat& image) {
  if (image.empty() || image.type() != CV_8UC1) throw InternalError("point front end: expects a CV_8UC1 image");
  return image;
}

/// Tracked points first (class_id = their index), then new detections (class_id = -1).
/// All are described upright (angle 0): tracked points have no orientation of their own,
/// and between neighbouring keyframes in-plane rotation is small.
std::vector<cv::KeyPoint> keypoints_to_describe(const std::vector<cv::Point2f>& tracked,
                                                std::vector<cv::KeyPoint> detected) {
  std::vector<cv::KeyPoint> all;
  all.reserve(tracked.size() + detected.size());
  for (size_t i = 0; i < tracked.size(); ++i)
    all.emplace_back(tracked[i], static_cast<float>(kOrbPatch), 0.f, 0.f, 0, static_cast<int>(i));
  for (auto& k : detected) {
    k.angle = 0.f;
    k.class_id = -1;
    all.push_back(k);
  }
  return all;
}

/// Describes with ORB; keypoints too close to the border are dropped by OpenCV, and
/// class_id tells which survived.
PointFeatures describe(cv::ORB& orb, const cv::Mat& image, std::vector<cv::KeyPoint> keypoints) {
  PointFeatures f;
  cv::Mat desc;
  if (!keypoints.empty()) orb.compute(image, keypoints, desc);
  for (const auto& k : keypoints) {
    f.points.push_back(k.pt);
    f.scores.push_back(k.response);
    f.source.push_back(k.class_id);
  }
  f.descriptors = desc.empty() ? cv::Mat(0, 32, CV_8U) : desc;
  return f;
}

int new_point_budget(const FrontendConfig& config, size_t tracked) {
  return std::max(0, config.max_points - static_cast<int>(tracked));
}

}  // namespace

OrbFrontend::OrbFrontend(const FrontendConfig& config) : config_(config) {
  orb_ = cv::ORB::create(config.max_points * 4, static_cast<float>(config.orb_scale_factor), config.orb_levels,
                         kOrbPatch, 0, 2, cv::ORB::HARRIS_SCORE, kOrbPatch, config.orb_fast_threshold);
}

PointFeatures OrbFrontend::detect(const cv::Mat& raw, const std::vector<cv::Point2f>& tracked) {
  const cv::Mat image = config_.equalize ? equalize_for_detection(checked_gray(raw)) : checked_gray(raw);
  std::vector<cv::KeyPoint> kept;
  const int budget = new_point_budget(config_, tracked.size());
  if (budget > 0) {
    const cv::Mat mask = free_space_mask(image.size(), tracked, config_.min_distance_px, kOrbPatch / 2 + 1);
    std::vector<cv::KeyPoint> kps;
    orb_->detect(image, kps, mask);
    std::vector<cv::Point2f> pts;
    std::vector<float> scores;
    for (const auto& k : kps) {
      pts.push_back(k.pt);
      scores.push_back(k.response);
    }
    for (size_t i : select_on_grid(pts, scores, image.size(), config_.grid_cols, config_.grid_rows, budget))
      kept.push_back(kps[i]);
  }
  return describe(*orb_, image, keypoints_to_describe(tracked, std::move(kept)));
}

ShiTomasiFrontend::ShiTomasiFrontend(const FrontendConfig& config) : config_(config) {
  describer_ = cv::ORB::create(config.max_points, 1.2f, 1, kOrbPatch, 0, 2, cv::ORB::HARRIS_SCORE, kOrbPatch);
}

PointFeatures ShiTomasiFrontend::detect(const cv::Mat& raw, const std::vector<cv::Point2f>& tracked) {
  const cv::Mat image = config_.equalize ? equalize_for_detection(checked_gray(raw)) : checked_gray(raw);
  std::vector<cv::KeyPoint> kept;
  const int budget = new_point_budget(config_, tracked.size());
  if (budget > 0) {
    const cv::Mat mask = free_space_mask(image.size(), tracked, config_.min_distance_px, kOrbPatch / 2 + 1);
    // More candidates than needed, then a grid selection: goodFeaturesToTrack alone piles
    // points onto the most textured region.
    std::vector<cv::Point2f> corners;
    cv::goodFeaturesToTrack(image, corners, budget * 3, config_.shitomasi_quality, config_.min_distance_px, mask,
                            config_.shitomasi_block_size, false);
    // goodFeaturesToTrack returns corners strongest first: the rank is the score.
    std::vector<float> scores(corners.size());
    for (size_t i = 0; i < corners.size(); ++i) scores[i] = static_cast<float>(corners.size() - i);
    for (size_t i : select_on_grid(corners, scores, image.size(), config_.grid_cols, config_.grid_rows, budget))
      kept.emplace_back(corners[i], static_cast<float>(kOrbPatch), 0.f, scores[i], 0);
  }
  return describe(*describer_, image, keypoints_to_describe(tracked, std::move(kept)));
}

}  // namespace pllvo::vo
