#include "pllvo/nn/superpoint_postprocess.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <opencv2/imgproc.hpp>

#include "pllvo/common/error.h"

namespace pllvo::nn {
namespace {

// Max over a (2r+1)^2 window with -inf padding (max_pool2d, stride 1, padding r).
// OpenCV's dilation with the default border value is exactly that, and exact (a max).
cv::Mat max_pool(const cv::Mat& m, int radius) {
  cv::Mat out;
  cv::dilate(m, out, cv::getStructuringElement(cv::MORPH_RECT, {2 * radius + 1, 2 * radius + 1}));
  return out;
}

}  // namespace

ScoreMap simple_nms(const ScoreMap& scores, int radius) {
  if (radius < 0) throw InternalError("simple_nms: negative radius");
  ScoreMap out = scores;
  if (scores.size() == 0) return out;
  const cv::Mat s(static_cast<int>(scores.rows()), static_cast<int>(scores.cols()), CV_32F,
                  const_cast<float*>(scores.data()));
  cv::Mat max_mask = s == max_pool(s, radius);
  for (int iteration = 0; iteration < 2; ++iteration) {
    const cv::Mat supp_mask = max_pool(max_mask, radius);  // 255 where a kept maximum is near
    cv::Mat supp_scores = s.clone();
    supp_scores.setTo(0.0f, supp_mask);
    const cv::Mat new_max_mask = supp_scores == max_pool(supp_scores, radius);
    max_mask |= new_max_mask & ~supp_mask;
  }
  cv::Mat result(s.rows, s.cols, CV_32F, out.data());
  result.setTo(0.0f, ~max_mask);
  return out;
}

KeypointCandidates find_candidates(const ScoreMap& scores, int nms_radius, int remove_borders) {
  const ScoreMap nms = simple_nms(scores, nms_radius);
  KeypointCandidates c;
  c.width = static_cast<int>(scores.cols());
  c.height = static_cast<int>(scores.rows());
  const int b = std::max(remove_borders, 0);
  for (int y = b; y < c.height - b; ++y) {
    const float* row = nms.data() + static_cast<std::ptrdiff_t>(y) * c.width;
    for (int x = b; x < c.width - b; ++x) {
      if (row[x] > 0.0f) {
        c.x.push_back(x);
        c.y.push_back(y);
        c.score.push_back(row[x]);
      }
    }
  }
  return c;
}

std::vector<std::int32_t> select_keypoints(const KeypointCandidates& candidates, float threshold,
                                           int max_keypoints) {
  std::vector<std::int32_t> kept;
  for (std::size_t i = 0; i < candidates.size(); ++i)
    if (candidates.score[i] > threshold) kept.push_back(static_cast<std::int32_t>(i));
  if (max_keypoints > 0 && kept.size() > static_cast<std::size_t>(max_keypoints)) {
    const auto by_score = [&](std::int32_t a, std::int32_t b) {
      const float sa = candidates.score[a], sb = candidates.score[b];
      return sa > sb || (sa == sb && a < b);
    };
    std::partial_sort(kept.begin(), kept.begin() + max_keypoints, kept.end(), by_score);
    kept.resize(max_keypoints);
  }
  return kept;
}

DescriptorMatrix sample_descriptors(const SuperPointDense& dense, const KeypointMatrix& keypoints) {
  const int w = dense.cells_w, h = dense.cells_h;
  const auto dim = dense.descriptors.cols();
  DescriptorMatrix out = DescriptorMatrix::Zero(keypoints.rows(), dim);
  if (w <= 0 || h <= 0) return out;
  // Same float operations as the official sample_descriptors + grid_sample(align_corners=True):
  // p' = p - s/2 + 0.5; p' /= (w*s - s/2 - 0.5); g = p'*2 - 1; i = (g + 1) * ((size - 1) / 2).
  const float div_x = static_cast<float>(w * 8 - 4.5), div_y = static_cast<float>(h * 8 - 4.5);
  const float half_x = static_cast<float>(w - 1) / 2.0f, half_y = static_cast<float>(h - 1) / 2.0f;
  for (Eigen::Index k = 0; k < keypoints.rows(); ++k) {
    const float gx = (keypoints(k, 0) - 4.0f + 0.5f) / div_x * 2.0f - 1.0f;
    const float gy = (keypoints(k, 1) - 4.0f + 0.5f) / div_y * 2.0f - 1.0f;
    const float ix = (gx + 1.0f) * half_x, iy = (gy + 1.0f) * half_y;
    const float x0 = std::floor(ix), y0 = std::floor(iy);
    const float tx = ix - x0, ty = iy - y0;
    const int cx = static_cast<int>(x0), cy = static_cast<int>(y0);
    const std::pair<int, float> xs[2] = {{cx, x0 + 1.0f - ix}, {cx + 1, tx}};
    const std::pair<int, float> ys[2] = {{cy, y0 + 1.0f - iy}, {cy + 1, ty}};
    auto row = out.row(k);
    for (const auto& [yy, wy] : ys) {
      for (const auto& [xx, wx] : xs) {
        if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;  // zero padding
        row += (wx * wy) * dense.descriptors.row(static_cast<Eigen::Index>(yy) * w + xx);
      }
    }
    row /= std::max(row.norm(), 1e-12f);
  }
  return out;
}

Features extract_features(const SuperPointDense& dense, const KeypointCandidates& candidates,
                          const std::vector<std::int32_t>& selected) {
  Features f;
  const auto n = static_cast<Eigen::Index>(selected.size());
  f.keypoints.resize(n, 2);
  f.scores.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto c = selected[static_cast<std::size_t>(i)];
    f.keypoints(i, 0) = static_cast<float>(candidates.x[c]);
    f.keypoints(i, 1) = static_cast<float>(candidates.y[c]);
    f.scores(i) = candidates.score[c];
  }
  f.descriptors = sample_descriptors(dense, f.keypoints);
  if (dense.scale != Eigen::Vector2f::Ones()) {
    for (Eigen::Index i = 0; i < n; ++i)
      for (int a = 0; a < 2; ++a) f.keypoints(i, a) = (f.keypoints(i, a) + 0.5f) * dense.scale[a] - 0.5f;
  }
  f.image_size = dense.image_size;
  return f;
}

}  // namespace pllvo::nn
