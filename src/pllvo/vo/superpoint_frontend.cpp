#include "pllvo/vo/superpoint_frontend.h"

#include <algorithm>
#include <cmath>

#include <spdlog/spdlog.h>

#include "pllvo/common/error.h"
#include "pllvo/nn/model_files.h"
#include "pllvo/nn/runtime.h"
#include "pllvo/nn/superpoint_postprocess.h"

namespace pllvo::vo {
namespace {

nn::SuperPointConfig network_config(const FrontendConfig& c) {
  nn::SuperPointConfig s;
  s.weights = c.superpoint_weights;
  s.nms_radius = c.superpoint_nms_radius;
  s.detection_threshold = static_cast<float>(c.superpoint_threshold);
  s.downscale = 1.0 / c.superpoint_input_scale;
  s.conv_layout = c.superpoint_conv_layout;
  s.validate();
  return s;
}

nn::AdaptiveThresholdConfig threshold_config(const FrontendConfig& c) {
  nn::AdaptiveThresholdConfig a;
  // Candidates beyond the point budget are only spread over the grid afterwards, so the
  // rule aims a little above it.
  a.target_keypoints = std::max(1, c.max_points * 3 / 2);
  a.max_keypoints = c.max_points * 4;
  a.min_threshold = std::min(a.min_threshold, static_cast<float>(c.superpoint_threshold));
  a.grid_cols = c.grid_cols;
  a.grid_rows = c.grid_rows;
  // Keyframe matching is judged against the point budget, not the network's usual 1000+.
  a.poor_matches = std::max(10, c.max_points / 8);
  a.good_matches = std::max(20, c.max_points / 3);
  a.validate();
  return a;
}

nn::SuperPoint load_network(const FrontendConfig& config) {
  // Activations recur every keyframe: keep freed memory instead of fresh mmaps. The thread
  // count is the run's (run.network_threads, set by Odometry).
  nn::keep_freed_memory();
  nn::SuperPoint sp(network_config(config));
  spdlog::info("SuperPoint front end: weights {}, input scale {}", sp.weights_file().string(),
               config.superpoint_input_scale);
  return sp;
}

/// Network-input pixels of an original-image pixel (inverse of (k + 0.5) s - 0.5).
Eigen::Vector2f to_network(const cv::Point2f& p, const Eigen::Vector2f& scale) {
  return {(p.x + 0.5f) / scale.x() - 0.5f, (p.y + 0.5f) / scale.y() - 0.5f};
}

float score_at(const nn::SuperPointDense& dense, const Eigen::Vector2f& q) {
  const int x = std::clamp(static_cast<int>(std::lround(q.x())), 0, static_cast<int>(dense.scores.cols()) - 1);
  const int y = std::clamp(static_cast<int>(std::lround(q.y())), 0, static_cast<int>(dense.scores.rows()) - 1);
  return dense.scores(y, x);
}

}  // namespace

SuperPointFrontend::SuperPointFrontend(const FrontendConfig& config)
    : config_(config), superpoint_(load_network(config)), threshold_(threshold_config(config)) {}

PointFeatures SuperPointFrontend::detect(const cv::Mat& raw, const std::vector<cv::Point2f>& tracked) {
  if (raw.empty() || raw.type() != CV_8UC1) throw InternalError("point front end: expects a CV_8UC1 image");
  const cv::Mat image = config_.superpoint_equalize ? equalize_for_detection(raw) : raw;
  const nn::SuperPointDense dense = superpoint_.run_network(image);
  const nn::KeypointCandidates candidates =
      nn::find_candidates(dense.scores, superpoint_.config().nms_radius, superpoint_.config().remove_borders);
  std::vector<std::int32_t> selected;
  if (config_.superpoint_adaptive_threshold) {
    std::lock_guard<std::mutex> lock(threshold_mutex_);  // report_matches may run on the other keyframe stage
    selected = threshold_.select(candidates);
  } else {
    selected = nn::select_keypoints(candidates, static_cast<float>(config_.superpoint_threshold), config_.max_points * 4);
  }

  PointFeatures out;
  // Tracked points first, described where they are.
  const int border = superpoint_.config().remove_borders;
  const cv::Rect inside(border, border, raw.cols - 2 * border, raw.rows - 2 * border);
  std::vector<int> tracked_kept;
  for (size_t i = 0; i < tracked.size(); ++i)
    if (inside.contains(cv::Point(cvFloor(tracked[i].x), cvFloor(tracked[i].y)))) tracked_kept.push_back(static_cast<int>(i));
  nn::KeypointMatrix query(static_cast<Eigen::Index>(tracked_kept.size()), 2);
  for (size_t k = 0; k < tracked_kept.size(); ++k) {
    const Eigen::Vector2f q = to_network(tracked[tracked_kept[k]], dense.scale);
    query.row(static_cast<Eigen::Index>(k)) = q.transpose();
    out.points.push_back(tracked[tracked_kept[k]]);
    out.scores.push_back(score_at(dense, q));
    out.source.push_back(tracked_kept[k]);
  }
  const nn::DescriptorMatrix tracked_desc = nn::sample_descriptors(dense, query);

  // New detections: away from tracked points, spread over the grid, within the budget.
  const nn::Features detected = nn::extract_features(dense, candidates, selected);
  const int budget = std::max(0, config_.max_points - static_cast<int>(out.points.size()));
  std::vector<int> picked;
  if (budget > 0 && detected.size() > 0) {
    const cv::Mat mask = free_space_mask(raw.size(), tracked, config_.min_distance_px, border);
    std::vector<cv::Point2f> pts;
    std::vector<float> scores;
    std::vector<int> index;
    for (int i = 0; i < detected.size(); ++i) {
      const cv::Point2f p(detected.keypoints(i, 0), detected.keypoints(i, 1));
      const cv::Point c(cvRound(p.x), cvRound(p.y));
      if (c.x < 0 || c.y < 0 || c.x >= mask.cols || c.y >= mask.rows || !mask.at<unsigned char>(c)) continue;
      pts.push_back(p);
      scores.push_back(detected.scores(i));
      index.push_back(i);
    }
    for (size_t k : select_on_grid(pts, scores, raw.size(), config_.grid_cols, config_.grid_rows, budget))
      picked.push_back(index[k]);
  }
  const int dim = superpoint_.descriptor_dim();
  out.descriptors.create(static_cast<int>(tracked_kept.size() + picked.size()), dim, CV_32F);
  for (int r = 0; r < static_cast<int>(tracked_kept.size()); ++r)
    std::copy_n(tracked_desc.row(r).data(), dim, out.descriptors.ptr<float>(r));
  for (size_t k = 0; k < picked.size(); ++k) {
    const int i = picked[k];
    const int r = static_cast<int>(tracked_kept.size() + k);
    std::copy_n(detected.descriptors.row(i).data(), dim, out.descriptors.ptr<float>(r));
    out.points.emplace_back(detected.keypoints(i, 0), detected.keypoints(i, 1));
    out.scores.push_back(detected.scores(i));
    out.source.push_back(-1);
  }
  return out;
}

void SuperPointFrontend::report_matches(int matched, int keypoints) {
  if (!config_.superpoint_adaptive_threshold) return;
  std::lock_guard<std::mutex> lock(threshold_mutex_);
  threshold_.report_matches(matched, keypoints);
}

std::optional<std::filesystem::path> find_superpoint_weights(const FrontendConfig& config) {
  return nn::find_weights(config.superpoint_weights, nn::superpoint_weight_names()).found;
}

}  // namespace pllvo::vo
