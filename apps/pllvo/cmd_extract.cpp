// pllvo extract: SuperPoint keypoints and descriptors of one image, to safetensors.
#include <cstdio>

#include <opencv2/imgcodecs.hpp>

#include "commands.h"
#include "pllvo/common/error.h"
#include "pllvo/nn/runtime.h"
#include "pllvo/nn/superpoint.h"

namespace pllvo::cli {

void add_extract_command(CLI::App& app) {
  struct Options {
    std::string image, out, weights;
    int max_keypoints = -1;
    float threshold = nn::SuperPointConfig{}.detection_threshold;
    double downscale = 1.0;
    int threads = 0;
  };
  auto opt = std::make_shared<Options>();
  auto* cmd = app.add_subcommand("extract", "SuperPoint keypoints, scores and descriptors of an image (safetensors)");
  cmd->add_option("image", opt->image, "8-bit image (converted to grayscale)")->required();
  cmd->add_option("--out", opt->out, "output .safetensors: keypoints [N,2] (x,y pixels), scores [N], descriptors [N,D], image_size")
      ->required();
  cmd->add_option("--weights", opt->weights,
                  "SuperPoint weights (.safetensors); default: superpoint_v1.safetensors in $PLLVO_MODELS, then models/");
  cmd->add_option("--max-keypoints", opt->max_keypoints, "keep the N best keypoints (default: all)");
  cmd->add_option("--threshold", opt->threshold, "keep scores strictly above this")->capture_default_str();
  cmd->add_option("--downscale", opt->downscale, "shrink the image by this factor before the network")->capture_default_str();
  cmd->add_option("--threads", opt->threads, "LibTorch and OpenBLAS threads (default: runtime default)");
  cmd->callback([opt] {
    nn::set_num_threads(opt->threads);
    nn::keep_freed_memory();
    const cv::Mat image = cv::imread(opt->image, cv::IMREAD_GRAYSCALE);
    if (image.empty()) throw InputError(opt->image, "cannot read the image");
    nn::SuperPointConfig config;
    config.weights = opt->weights;
    config.detection_threshold = opt->threshold;
    config.max_keypoints = opt->max_keypoints;
    config.downscale = opt->downscale;
    const nn::SuperPoint superpoint(config);
    const auto features = superpoint.detect(image);
    nn::save_features(features, opt->out);
    std::printf("%d keypoints (%s) -> %s\n", features.size(), superpoint.weights_file().c_str(), opt->out.c_str());
  });
}

}  // namespace pllvo::cli
