// scripts/convert_weights.py end to end: official-layout .pth files written with torch.save
// from the random test weights are converted back to safetensors; every tensor must come back
// identical, and the converted LightGlue must reproduce a reference vector.
#include <gtest/gtest.h>
#include <unistd.h>

#include "nn_test_util.h"
#include "pllvo/nn/lightglue.h"
#include "pllvo/nn/superpoint.h"

namespace pllvo::nn {
namespace {

namespace fs = std::filesystem;

class ConvertWeights : public ::testing::Test {
 protected:
  void SetUp() override {
    python_ = test::python_with_torch();
    ASSERT_FALSE(python_.empty()) << "no python3 with torch (Debian: python3-torch); set PLLVO_PYTHON";
    dir_ = fs::temp_directory_path() / ("pllvo_convert_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // safetensors -> official .pth -> converted safetensors; returns the converted file.
  fs::path round_trip(const fs::path& weights) {
    const fs::path pth = dir_ / (weights.stem().string() + ".pth");
    const fs::path out = dir_ / (weights.stem().string() + "_converted.safetensors");
    const std::string src = PLLVO_SOURCE_DIR;
    std::string log;
    EXPECT_EQ(test::run_command(python_ + " " + src + "/tests/nn/write_official_pth.py " + weights.string() + " " + pth.string(), log), 0) << log;
    EXPECT_EQ(test::run_command(python_ + " " + src + "/scripts/convert_weights.py " + pth.string() + " " + out.string(), log), 0) << log;
    return out;
  }

  static void expect_identical(const SafeTensors& original, const SafeTensors& converted) {
    for (const auto& name : original.names()) {
      if (name == "confidence_thresholds") {
        EXPECT_FALSE(converted.contains(name)) << "the released checkpoint layout has no buffer";
        continue;
      }
      ASSERT_TRUE(converted.contains(name)) << name;
      EXPECT_EQ(converted.at(name).shape, original.at(name).shape) << name;
      EXPECT_EQ(converted.at(name).dtype, DType::F32) << name;
      EXPECT_EQ(converted.floats(name), original.floats(name)) << name;
    }
    EXPECT_EQ(converted.size(), original.size() - (original.contains("confidence_thresholds") ? 1 : 0));
  }

  std::string python_;
  fs::path dir_;
};

TEST_F(ConvertWeights, SuperPointRoundTripIsExact) {
  const auto weights = test::superpoint_vector("superpoint_random_weights.safetensors");
  const auto converted = SafeTensors::load(round_trip(weights));
  expect_identical(SafeTensors::load(weights), converted);
  EXPECT_NE(converted.metadata().at("licence").find("noncommercial"), std::string::npos);
  EXPECT_NO_THROW(SuperPoint(converted, {}));
}

TEST_F(ConvertWeights, LightGlueRoundTripRenamesAndReproducesVector) {
  const auto weights = test::lightglue_vector("lightglue_random_l3_d64.safetensors");
  const auto converted = SafeTensors::load(round_trip(weights));
  expect_identical(SafeTensors::load(weights), converted);
  EXPECT_EQ(converted.metadata().at("config"),
            R"({"input_dim": 256, "descriptor_dim": 64, "n_layers": 3, "num_heads": 4, "add_scale_ori": false})");

  LightGlueConfig config;
  config.depth_confidence = config.width_confidence = -1;
  const auto r = LightGlue(converted, config)
                     .match(load_features(test::superpoint_vector("icl250_640x480_k512.safetensors")),
                            load_features(test::superpoint_vector("icl254_640x480_k512.safetensors")));
  const auto ref = SafeTensors::load(test::lightglue_vector("c_pairA.safetensors")).ints("matches0");
  ASSERT_EQ(static_cast<std::size_t>(r.matches0.size()), ref.size());
  for (std::size_t i = 0; i < ref.size(); ++i) EXPECT_EQ(r.matches0(static_cast<Eigen::Index>(i)), ref[i]) << i;
}

TEST_F(ConvertWeights, UnknownCheckpointIsRejected) {
  const fs::path pth = dir_ / "other.pth";
  std::string log;
  ASSERT_EQ(test::run_command(python_ + " -c \"import torch; torch.save({'fc.weight': torch.zeros(2, 2)}, '" + pth.string() + "')\"", log), 0) << log;
  EXPECT_NE(test::run_command(python_ + " " + std::string(PLLVO_SOURCE_DIR) + "/scripts/convert_weights.py " + pth.string() + " " + (dir_ / "x.safetensors").string(), log), 0);
  EXPECT_NE(log.find("unrecognised checkpoint"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(dir_ / "x.safetensors"));
}

}  // namespace
}  // namespace pllvo::nn
