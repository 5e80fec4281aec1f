// pllvo match: LightGlue (or mutual nearest neighbours) between two feature files.
#include <cstdio>

#include "commands.h"
#include "pllvo/common/error.h"
#include "pllvo/nn/lightglue.h"
#include "pllvo/nn/matcher.h"
#include "pllvo/nn/runtime.h"

namespace pllvo::cli {

void add_match_command(CLI::App& app) {
  struct Options {
    std::string feats0, feats1, out, matcher = "lightglue";
    std::vector<std::string> weights;
    nn::LightGlueConfig lightglue;
    nn::MnnConfig mnn;
    int threads = 0;
  };
  auto opt = std::make_shared<Options>();
  auto* cmd = app.add_subcommand("match", "match two feature files (from pllvo extract) with LightGlue or MNN");
  cmd->add_option("feats0", opt->feats0, "features of image 0 (.safetensors)")->required();
  cmd->add_option("feats1", opt->feats1, "features of image 1 (.safetensors)")->required();
  cmd->add_option("--out", opt->out, "output .safetensors: matches [K,2], scores [K]; LightGlue adds stop, matches0/1, prune0/1")
      ->required();
  cmd->add_option("--matcher", opt->matcher, "lightglue (falls back to mnn when no weights are found) or mnn")
      ->check(CLI::IsMember({"lightglue", "mnn"}))
      ->capture_default_str();
  cmd->add_option("--weights", opt->weights,
                  "LightGlue weights; repeat to apply override files on top (later ones replace tensors). "
                  "Default: superpoint_lightglue.safetensors in $PLLVO_MODELS, then models/")
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  cmd->add_option("--depth-confidence", opt->lightglue.depth_confidence, "early-exit confidence (<= 0: off)")->capture_default_str();
  cmd->add_option("--width-confidence", opt->lightglue.width_confidence, "pruning confidence (<= 0: off)")->capture_default_str();
  cmd->add_option("--filter-threshold", opt->lightglue.filter_threshold, "minimum match score")->capture_default_str();
  cmd->add_option("--pruning-threshold", opt->lightglue.pruning_keypoint_threshold,
                  "prune only while an image has more points than this (-1: always, the official CPU rule)")
      ->capture_default_str();
  cmd->add_option("--ratio", opt->mnn.ratio_threshold, "MNN: ratio test (<= 0: off)")->capture_default_str();
  cmd->add_option("--max-distance", opt->mnn.distance_threshold, "MNN: maximum descriptor distance (<= 0: off)")->capture_default_str();
  cmd->add_option("--threads", opt->threads, "LibTorch and OpenBLAS threads (default: runtime default)");
  cmd->callback([opt] {
    nn::set_num_threads(opt->threads);
    nn::keep_freed_memory();
    const auto f0 = nn::load_features(opt->feats0);
    const auto f1 = nn::load_features(opt->feats1);
    nn::MatcherConfig config;
    config.type = opt->matcher;
    config.mnn = opt->mnn;
    config.lightglue = opt->lightglue;
    if (!opt->weights.empty()) {
      config.lightglue.weights = opt->weights.front();
      config.lightglue.weight_overrides.assign(opt->weights.begin() + 1, opt->weights.end());
    }
    config.lightglue.validate();
    const auto resolved = nn::resolve_matcher(config);  // MNN (with a warning) when no LightGlue weights are found
    if (resolved.type == "lightglue") {
      const nn::LightGlue lightglue(resolved.lightglue);
      const auto r = lightglue.match(f0, f1);
      nn::save_lightglue_result(r, opt->out);
      std::printf("lightglue: %d matches, stop after %d layers -> %s\n", r.matches.size(), r.stop, opt->out.c_str());
    } else {
      const auto m = nn::match_mutual_nearest(f0, f1, resolved.mnn);
      nn::save_matches(m, opt->out);
      std::printf("mnn: %d matches -> %s\n", m.size(), opt->out.c_str());
    }
  });
}

}  // namespace pllvo::cli
