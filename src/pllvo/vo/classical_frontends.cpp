#include "pllvo/vo/classical_frontends.h"

#include <opencv2/imgproc.hpp>

#include "pllvo/common/error.h"

namespace pllvo::vo {
namespace {

// ORB's descriptor needs a 31x31 patch (plus its edge threshold) around every point.
constexpr int kOrbPatch = 31;

PointFeatures from_keypoints(const std::vector<cv::KeyPoint>& kps, const cv::Mat& desc) {
  PointFeatures f;
  f.points.reserve(kps.size());
  for (const auto& k : kps) {
    f.points.push_back(k.pt);
    f.scores.push_back(k.response);
  }
  f.descriptors = desc.empty() ? cv::Mat(0, 32, CV_8U) : desc;
  return f;
}

cv::Mat checked_gray(const cv::Mat& image) {
  if (image.empty() || image.type() != CV_8UC1) throw InternalError("point front end: expects a CV_8UC1 image");
  return image;
}

}  // namespace

OrbFrontend::OrbFrontend(const FrontendConfig& config) : config_(config) {
  orb_ = cv::ORB::create(config.max_points * 4, static_cast<float>(config.orb_scale_factor), config.orb_levels,
                         kOrbPatch, 0, 2, cv::ORB::HARRIS_SCORE, kOrbPatch, config.orb_fast_threshold);
}

PointFeatures OrbFrontend::detect(const cv::Mat& raw, const std::vector<cv::Point2f>& occupied) {
  const cv::Mat image = config_.equalize ? equalize_for_detection(checked_gray(raw)) : checked_gray(raw);
  const cv::Mat mask = free_space_mask(image.size(), occupied, config_.min_distance_px, kOrbPatch / 2 + 1);
  std::vector<cv::KeyPoint> kps;
  orb_->detect(image, kps, mask);
  std::vector<cv::Point2f> pts;
  std::vector<float> scores;
  for (const auto& k : kps) {
    pts.push_back(k.pt);
    scores.push_back(k.response);
  }
  std::vector<cv::KeyPoint> kept;
  for (size_t i : select_on_grid(pts, scores, image.size(), config_.grid_cols, config_.grid_rows,
                                 config_.max_points))
    kept.push_back(kps[i]);
  cv::Mat desc;
  if (!kept.empty()) orb_->compute(image, kept, desc);
  return from_keypoints(kept, desc);
}

ShiTomasiFrontend::ShiTomasiFrontend(const FrontendConfig& config) : config_(config) {
  describer_ = cv::ORB::create(config.max_points, 1.2f, 1, kOrbPatch, 0, 2, cv::ORB::HARRIS_SCORE, kOrbPatch);
}

PointFeatures ShiTomasiFrontend::detect(const cv::Mat& raw, const std::vector<cv::Point2f>& occupied) {
  const cv::Mat image = config_.equalize ? equalize_for_detection(checked_gray(raw)) : checked_gray(raw);
  const cv::Mat mask = free_space_mask(image.size(), occupied, config_.min_distance_px, kOrbPatch / 2 + 1);
  // More candidates than needed, then a grid selection: goodFeaturesToTrack alone piles
  // points onto the most textured region.
  std::vector<cv::Point2f> corners;
  cv::goodFeaturesToTrack(image, corners, config_.max_points * 3, config_.shitomasi_quality,
                          config_.min_distance_px, mask, config_.shitomasi_block_size, false);
  if (corners.empty()) return from_keypoints({}, {});
  // goodFeaturesToTrack returns corners strongest first: rank is the score.
  std::vector<float> scores(corners.size());
  for (size_t i = 0; i < corners.size(); ++i) scores[i] = static_cast<float>(corners.size() - i);
  std::vector<cv::KeyPoint> kept;
  for (size_t i : select_on_grid(corners, scores, image.size(), config_.grid_cols, config_.grid_rows,
                                 config_.max_points)) {
    cv::KeyPoint k(corners[i], kOrbPatch, 0.f, scores[i], 0);
    kept.push_back(k);
  }
  cv::Mat desc;
  describer_->compute(image, kept, desc);
  return from_keypoints(kept, desc);
}

}  // namespace pllvo::vo
