#pragma once
// LightGlue (Lindenberger et al., ICCV 2023) exactly as the official code
// (cvg/LightGlue, lightglue/lightglue.py) computes it on a CPU, including its two
// adaptive mechanisms: adaptive depth (stop after a layer once enough points are
// confident) and adaptive width (prune points that are confidently unmatchable).
// The architecture comes from the weight file; LibTorch stays behind the pimpl.
#include <filesystem>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "pllvo/common/yaml_config.h"
#include "pllvo/nn/features.h"
#include "pllvo/nn/safetensors.h"

namespace pllvo::nn {

/// Shape of the network, read from the weights (tensor shapes; checked against the
/// `config` JSON in the file's metadata when present).
struct LightGlueArchitecture {
  int input_dim = 256;       ///< descriptor size of the features (SuperPoint: 256)
  int descriptor_dim = 256;  ///< width of the transformer (input_proj maps to it when different)
  int n_layers = 9;
  int num_heads = 4;
  bool add_scale_ori = false;  ///< SIFT/DISK-style scale+orientation input: not supported

  int head_dim() const { return descriptor_dim / num_heads; }
};

struct LightGlueConfig {
  /// Weights file or folder; empty: looked up as superpoint_lightglue.safetensors (model_files.h).
  std::filesystem::path weights;
  /// Files applied on top of `weights`, later ones replacing tensors of earlier ones.
  std::vector<std::filesystem::path> weight_overrides;
  float filter_threshold = 0.1f;   ///< a match needs a mutual argmax and score > this
  float depth_confidence = 0.95f;  ///< early exit when more than this fraction is confident; <= 0: off
  float width_confidence = 0.99f;  ///< prune points whose matchability < 1 - this; <= 0: off
  /// Prune only while an image has more points than this. The official code uses -1 on
  /// CPU (always), 1024 on CUDA; the reference vectors need -1.
  int pruning_keypoint_threshold = -1;

  static LightGlueConfig from_yaml(const ConfigNode& node);
  /// {key, problem} of the first invalid setting; empty when all are valid.
  std::pair<std::string, std::string> problem() const;
  void validate() const;  ///< InputError naming the key
};

struct LightGlueResult {
  Matches matches;                 ///< valid matches, ascending index0, with their scores
  Eigen::VectorXi matches0;        ///< M: index in image 1 or -1
  Eigen::VectorXi matches1;        ///< N: index in image 0 or -1
  Eigen::VectorXf matching_scores0;  ///< M: exp(row max) for every mutual pair (also below threshold), else 0
  Eigen::VectorXf matching_scores1;  ///< N
  int stop = 0;                    ///< transformer layers run
  Eigen::VectorXi prune0;          ///< M: layers each point went through
  Eigen::VectorXi prune1;          ///< N
};

/// Intermediate values, filled on request (tests, debugging).
struct LightGlueTrace {
  bool want_log_assignment = false;
  Eigen::MatrixXf log_assignment;                 ///< (M'+1) x (N'+1) over the points left at the end
  Eigen::MatrixXf keypoints_normalized0, keypoints_normalized1;  ///< M x 2, N x 2
  Eigen::MatrixXf posenc_cos0, posenc_sin0;       ///< M x head_dim: the rotary encoding
  Eigen::MatrixXf posenc_cos1, posenc_sin1;
  Eigen::MatrixXf desc0_after_layer0, desc1_after_layer0;  ///< M x D, N x D
};

class LightGlue {
 public:
  /// Finds the weights (config path, $PLLVO_MODELS, repo models/), applies the overrides,
  /// loads them; InputError when none are found (make_matcher() falls back to MNN instead).
  explicit LightGlue(LightGlueConfig config);
  /// Weights already loaded: every tensor of the architecture must be present with its
  /// shape (InputError naming it); `confidence_thresholds` may be absent.
  LightGlue(const SafeTensors& weights, LightGlueConfig config);
  ~LightGlue();
  LightGlue(LightGlue&&) noexcept;
  LightGlue& operator=(LightGlue&&) noexcept;

  /// Matches two images' features; descriptors must have input_dim columns and
  /// image_size must be set (keypoints are normalised by it).
  LightGlueResult match(const Features& f0, const Features& f1, LightGlueTrace* trace = nullptr) const;

  const LightGlueArchitecture& architecture() const;
  const LightGlueConfig& config() const { return config_; }
  LightGlueConfig& mutable_config() { return config_; }  ///< thresholds may change between calls
  const std::filesystem::path& weights_file() const { return weights_file_; }

 private:
  struct Net;
  std::unique_ptr<Net> net_;
  LightGlueConfig config_;
  std::filesystem::path weights_file_;
};

/// Writes `matches` [K,2] I64, `scores` [K], `stop` [1] I64, `matches0/1`, `matching_scores0/1`
/// and `prune0/1` with the names and dtypes of the official outputs (testvectors/lightglue).
void save_lightglue_result(const LightGlueResult& result, const std::filesystem::path& file);

/// The tensors of `weights` under the official code's names: released checkpoints name layers
/// self_attn.{i}. / cross_attn.{i}., the official loader renames them transformers.{i}.self_attn. / .cross_attn.
SafeTensors with_official_names(const SafeTensors& weights);

/// The architecture a weight file holds, from its tensor shapes (InputError when it is not a
/// LightGlue file or disagrees with its metadata `config`).
LightGlueArchitecture lightglue_architecture(const SafeTensors& weights);

/// Loads `file` and applies `overrides` in order (their tensors replace or add to it).
SafeTensors load_weights_with_overrides(const std::filesystem::path& file,
                                        const std::vector<std::filesystem::path>& overrides);

}  // namespace pllvo::nn
