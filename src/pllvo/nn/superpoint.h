#pragma once
// SuperPoint (DeTone et al. 2018) exactly as the official code computes it: the network of
// Magic Leap's superpoint_v1.pth (VGG encoder, detector head with a 65-channel softmax and
// depth-to-space, descriptor head) followed by the LightGlue project's extractor
// post-processing (superpoint_postprocess.h). LibTorch stays behind the pimpl.
#include <filesystem>
#include <memory>
#include <string>

#include <opencv2/core/mat.hpp>

#include "pllvo/common/yaml_config.h"
#include "pllvo/nn/features.h"
#include "pllvo/nn/safetensors.h"
#include "pllvo/nn/superpoint_postprocess.h"

namespace pllvo::nn {

struct SuperPointConfig {
  /// Weights file or folder; empty: looked up as superpoint_v1.safetensors (model_files.h).
  std::filesystem::path weights;
  int nms_radius = 4;
  /// Keep scores strictly above this. 0.0005 is the LightGlue extractor's default (Magic
  /// Leap's demo uses 0.015); the adaptive threshold (adaptive_threshold.h) replaces it per frame.
  float detection_threshold = 0.0005f;
  int remove_borders = 4;      ///< pixels; 0 keeps the border
  int max_keypoints = -1;      ///< <= 0: keep all; else the best N by score
  /// > 1 shrinks the image by this factor (cv::INTER_AREA) before the network; keypoints are
  /// mapped back to full-resolution pixels with (k + 0.5) * s - 0.5, as LightGlue's extract().
  double downscale = 1.0;
  /// Memory layout of the convolutions (speed only; same function): "mkldnn" keeps the
  /// activations in oneDNN's blocked layout between layers and the weights pre-reordered
  /// (fastest, docs/nn.md), "channels_last" (NHWC), "nchw" (PyTorch's default).
  std::string conv_layout = "nchw";

  /// Defaults overridden by the keys present; InputError naming a bad key.
  static SuperPointConfig from_yaml(const ConfigNode& node);
  /// {key, problem} of the first invalid setting; empty when all are valid.
  std::pair<std::string, std::string> problem() const;
  void validate() const;  ///< InputError naming the key
};

class SuperPoint {
 public:
  /// Finds the weights (config path, $PLLVO_MODELS, repo models/) and loads them;
  /// InputError saying where it looked when there are none.
  explicit SuperPoint(SuperPointConfig config);
  /// Uses weights already loaded (24 tensors, official names; F32 or F16). Shapes are checked;
  /// a missing, extra or misshapen tensor is an InputError naming it.
  SuperPoint(const SafeTensors& weights, SuperPointConfig config);
  ~SuperPoint();
  SuperPoint(SuperPoint&&) noexcept;
  SuperPoint& operator=(SuperPoint&&) noexcept;

  /// The network on an 8-bit grayscale image (CV_8UC1; CV_32FC1 in [0, 1] also accepted),
  /// after the optional downscaling. InputError for another image type or an image < 8 px.
  SuperPointDense run_network(const cv::Mat& image) const;

  /// Network + post-processing with the configured threshold and max_keypoints.
  Features detect(const cv::Mat& image) const;
  Features detect(const cv::Mat& image, float threshold, int max_keypoints) const;

  int descriptor_dim() const;
  const SuperPointConfig& config() const { return config_; }
  const std::filesystem::path& weights_file() const { return weights_file_; }

 private:
  struct Net;
  std::unique_ptr<Net> net_;
  SuperPointConfig config_;
  std::filesystem::path weights_file_;
};

}  // namespace pllvo::nn
