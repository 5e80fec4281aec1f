// `pllvo extract` and `pllvo match` reproduce the reference vectors from the command line.
#include <gtest/gtest.h>
#include <unistd.h>

#include "nn_test_util.h"
#include "pllvo/nn/features.h"
#include "pllvo/nn/model_files.h"

namespace pllvo::nn {
namespace {

namespace fs = std::filesystem;
using test::max_abs_diff;

class NnCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("pllvo_cli_nn_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  int run(const std::string& args, std::string& output, const std::string& env = "") const {
    return test::run_command(env + " " + std::string(PLLVO_CLI_PATH) + " " + args + " --threads 1", output);
  }
  static std::string sp(const std::string& name) { return test::superpoint_vector(name).string(); }
  static std::string lg(const std::string& name) { return test::lightglue_vector(name).string(); }

  fs::path dir_;
};

TEST_F(NnCli, ExtractReproducesSuperPointVectors) {
  for (const std::string config : {"k512", "kall"}) {
    const auto out = dir_ / (config + ".safetensors");
    std::string log;
    const std::string max = config == "k512" ? " --max-keypoints 512" : "";
    ASSERT_EQ(run("extract " + sp("icl250_640x480.png") + " --out " + out.string() + " --weights " +
                      sp("superpoint_random_weights.safetensors") + " --threshold 0.0005" + max,
                  log),
              0)
        << log;
    const auto ref = SafeTensors::load(sp("icl250_640x480_" + config + ".safetensors"));
    const auto got = SafeTensors::load(out);
    EXPECT_EQ(got.at("keypoints").shape, ref.at("keypoints").shape);
    EXPECT_EQ(got.floats("keypoints"), ref.floats("keypoints")) << "same keypoints in the same order";
    const auto scores = got.floats("scores");
    EXPECT_LE(max_abs_diff(ref.floats("keypoint_scores"), scores.data(), scores.size()), 1e-5);
    const auto desc = got.floats("descriptors");
    EXPECT_LE(max_abs_diff(ref.floats("descriptors"), desc.data(), desc.size()), 1e-4);
    EXPECT_EQ(got.ints("image_size"), ref.ints("image_size"));
  }
}

TEST_F(NnCli, MatchReproducesLightGlueVectorWithAdaptivity) {
  const auto out = dir_ / "b_pairA.safetensors";
  std::string log;
  ASSERT_EQ(run("match " + sp("icl250_640x480_k512.safetensors") + " " + sp("icl254_640x480_k512.safetensors") + " --out " +
                    out.string() + " --weights " + lg("lightglue_sp_random_l9_d256.safetensors") + " --weights " +
                    lg("lightglue_sp_random_l9_d256_b_token_confidence.safetensors") +
                    " --depth-confidence 0.6 --width-confidence 0.25",
                log),
            0)
      << log;
  const auto ref = SafeTensors::load(lg("b_pairA.safetensors"));
  const auto got = SafeTensors::load(out);
  for (const char* name : {"matches", "stop", "matches0", "matches1", "prune0", "prune1"})
    EXPECT_EQ(got.ints(name), ref.ints(name)) << name;
  EXPECT_EQ(got.ints("stop"), std::vector<std::int64_t>{7});
  const auto scores = got.floats("scores");
  EXPECT_LE(max_abs_diff(ref.floats("scores"), scores.data(), scores.size()), 1e-4);
}

TEST_F(NnCli, MatchWithoutLightGlueWeightsFallsBackToMnn) {
  // $PLLVO_MODELS replaces the repository's models/ (which ships pllvo's LightGlue): an empty folder.
  const auto out = dir_ / "mnn.safetensors";
  std::string log;
  ASSERT_EQ(run("match " + sp("icl250_640x480_k512.safetensors") + " " + sp("icl254_640x480_k512.safetensors") + " --out " +
                    out.string(),
                log, "PLLVO_MODELS=" + dir_.string()),
            0)
      << log;
  EXPECT_NE(log.find("not found"), std::string::npos) << log;
  EXPECT_NE(log.find("falling back to the mutual-nearest-neighbour matcher"), std::string::npos) << log;
  const auto got = SafeTensors::load(out);
  EXPECT_FALSE(got.contains("stop"));
  EXPECT_GT(got.at("matches").shape[0], 50);
}

TEST_F(NnCli, BadInputsAreReportedWithExitCode2) {
  std::string log;
  EXPECT_EQ(run("extract " + (dir_ / "missing.png").string() + " --out " + (dir_ / "x.safetensors").string() + " --weights " +
                    sp("superpoint_random_weights.safetensors"),
                log),
            2);
  EXPECT_NE(log.find("pllvo: error: "), std::string::npos) << log;
  EXPECT_NE(log.find("missing.png"), std::string::npos) << log;
  EXPECT_EQ(run("match " + sp("icl250_640x480_k512.safetensors") + " " + sp("icl254_640x480_k512.safetensors") + " --out " +
                    (dir_ / "y.safetensors").string() + " --weights " + (dir_ / "nope.safetensors").string(),
                log),
            2);
  EXPECT_NE(log.find("nope.safetensors"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(dir_ / "y.safetensors"));
}

}  // namespace
}  // namespace pllvo::nn
