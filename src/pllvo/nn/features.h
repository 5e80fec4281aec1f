#pragma once
// Keypoints with descriptors (what SuperPoint produces and matchers consume) and matches,
// as plain Eigen types so that no module outside nn/ needs LibTorch headers.
#include <filesystem>

#include <Eigen/Core>

namespace pllvo::nn {

using KeypointMatrix = Eigen::Matrix<float, Eigen::Dynamic, 2, Eigen::RowMajor>;
using DescriptorMatrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using MatchMatrix = Eigen::Matrix<int, Eigen::Dynamic, 2, Eigen::RowMajor>;

/// Keypoints of one image. Pixel convention of the official SuperPoint/LightGlue code:
/// (x, y) = (column, row), the centre of pixel (0, 0) is (0, 0).
struct Features {
  KeypointMatrix keypoints;      ///< N x 2, (x, y) in pixels
  Eigen::VectorXf scores;        ///< N detector scores
  DescriptorMatrix descriptors;  ///< N x D, rows L2-normalised
  Eigen::Vector2i image_size{0, 0};  ///< (width, height) of the image the keypoints live in

  int size() const { return static_cast<int>(keypoints.rows()); }
};

/// Correspondences between two feature sets.
struct Matches {
  MatchMatrix pairs;        ///< K x 2 (index0, index1), ascending index0
  Eigen::VectorXf scores;   ///< K match confidences (matcher-specific, higher is better)
  /// LightGlue's adaptivity on this pair (0 for other matchers): transformer layers run, and the
  /// share of points pruned before the last layer run.
  int layers_run = 0;
  float pruned_share = 0.0f;

  int size() const { return static_cast<int>(pairs.rows()); }
};

/// Writes `keypoints` [N,2] F32, `scores` [N] F32, `descriptors` [N,D] F32, `image_size` [2] I64.
void save_features(const Features& features, const std::filesystem::path& file);

/// Reads a features file: pllvo's own (`scores`) or the official test vectors'
/// (`keypoint_scores`); `image_size` is required (LightGlue normalises by it).
/// InputError naming the file and tensor on a missing tensor or inconsistent shapes.
Features load_features(const std::filesystem::path& file);

/// Writes `matches` [K,2] I64 (index0, index1) and `scores` [K] F32.
void save_matches(const Matches& matches, const std::filesystem::path& file);

}  // namespace pllvo::nn
