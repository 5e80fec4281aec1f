#pragma once
// SuperPoint's post-processing as the LightGlue project's extractor does it (torch-free):
// NMS, border removal, strict score threshold, top-k, bilinear descriptor sampling.
// The network runs once per image (SuperPoint::run_network); selecting keypoints from its
// dense output is cheap, so the adaptive threshold can re-select without re-running it.
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "pllvo/nn/features.h"

namespace pllvo::nn {

using ScoreMap = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// The network's dense output for one image.
struct SuperPointDense {
  ScoreMap scores;               ///< (8h) x (8w) keypoint probability, before NMS (dustbin dropped)
  DescriptorMatrix descriptors;  ///< (h*w) x D, cell (y, x) at row y*w + x, L2-normalised
  int cells_w = 0;               ///< w = floor(W / 8)
  int cells_h = 0;               ///< h = floor(H / 8)
  Eigen::Vector2i image_size{0, 0};  ///< (W, H) of the original image
  /// Network-input pixels to original pixels, (k + 0.5) * scale - 0.5 (1 without downscaling).
  Eigen::Vector2f scale{1.0f, 1.0f};
};

/// Official `simple_nms`: a point survives if it equals the max over its (2r+1)^2 window,
/// then two rounds recover maxima whose window holds no surviving point. Ties all survive.
/// Suppressed entries become 0.
ScoreMap simple_nms(const ScoreMap& scores, int radius);

/// Local maxima inside the border band, with score > 0, in row-major (y, then x) order:
/// every keypoint any threshold >= 0 can select.
struct KeypointCandidates {
  std::vector<std::int32_t> x, y;
  std::vector<float> score;
  int width = 0, height = 0;  ///< of the score map

  std::size_t size() const { return score.size(); }
};
KeypointCandidates find_candidates(const ScoreMap& scores, int nms_radius, int remove_borders);

/// Keeps candidates with score > threshold (strict) in row-major order; when more than
/// max_keypoints (> 0) remain, the best max_keypoints in descending score order (ties:
/// row-major order). Returns candidate indices.
std::vector<std::int32_t> select_keypoints(const KeypointCandidates& candidates, float threshold,
                                           int max_keypoints);

/// Bilinear sampling of the dense descriptors at pixel keypoints with the official
/// convention (grid_sample, align_corners=True, zero padding) and L2 normalisation.
DescriptorMatrix sample_descriptors(const SuperPointDense& dense, const KeypointMatrix& keypoints);

/// Keypoints, scores and descriptors of the selected candidates; keypoints in original
/// image pixels (see SuperPointDense::scale).
Features extract_features(const SuperPointDense& dense, const KeypointCandidates& candidates,
                          const std::vector<std::int32_t>& selected);

}  // namespace pllvo::nn
