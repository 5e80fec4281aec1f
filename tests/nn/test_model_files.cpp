// Weight lookup: configured path, else one folder ($PLLVO_MODELS or the repository's models/), where the
// official file names come before pllvo's own; and pllvo's shipped weights load as the default.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>

#include "pllvo/common/error.h"
#include "pllvo/nn/lightglue.h"
#include "pllvo/nn/model_files.h"
#include "pllvo/nn/superpoint.h"

namespace pllvo::nn {
namespace {

namespace fs = std::filesystem;

class ModelFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("pllvo_model_files_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    if (const char* env = std::getenv("PLLVO_MODELS")) saved_ = env;
    ::unsetenv("PLLVO_MODELS");
  }
  void TearDown() override {
    if (saved_) ::setenv("PLLVO_MODELS", saved_->c_str(), 1);
    else ::unsetenv("PLLVO_MODELS");
    fs::remove_all(dir_);
  }
  void touch(const std::string& name) const { std::ofstream(dir_ / name) << "x"; }

  fs::path dir_;
  std::optional<std::string> saved_;
};

TEST_F(ModelFiles, RepositoryShipsPllvoWeightsAndTheyAreTheDefault) {
  ASSERT_TRUE(fs::is_regular_file(repository_models_dir() / kPllvoSuperPointWeights));
  ASSERT_TRUE(fs::is_regular_file(repository_models_dir() / kPllvoLightGlueWeights));
  const auto sp = find_weights({}, superpoint_weight_names());
  ASSERT_TRUE(sp.found);
  // Unless a user converted the official file into models/, pllvo's own is found.
  if (!fs::exists(repository_models_dir() / kSuperPointWeights))
    EXPECT_EQ(sp.found->filename(), kPllvoSuperPointWeights);
  const SuperPoint net{SuperPointConfig{}};
  EXPECT_EQ(net.descriptor_dim(), 256);
  const LightGlue matcher{LightGlueConfig{}};
  EXPECT_EQ(matcher.architecture().n_layers, 6);
  EXPECT_EQ(matcher.architecture().descriptor_dim, 256);
}

TEST_F(ModelFiles, EnvironmentFolderReplacesTheRepositoryFolder) {
  ::setenv("PLLVO_MODELS", dir_.c_str(), 1);
  auto search = find_weights({}, lightglue_weight_names());
  EXPECT_FALSE(search.found);
  ASSERT_EQ(search.tried.size(), 2u);
  EXPECT_EQ(search.tried[0], dir_ / kLightGlueWeights);
  EXPECT_EQ(search.tried[1], dir_ / kPllvoLightGlueWeights);
  EXPECT_NE(search.not_found_message().find(kPllvoLightGlueWeights), std::string::npos);
  touch(kPllvoLightGlueWeights);
  EXPECT_EQ(find_weights({}, lightglue_weight_names()).found, dir_ / kPllvoLightGlueWeights);
  touch(kLightGlueWeights);  // official weights a user converted come first
  EXPECT_EQ(find_weights({}, lightglue_weight_names()).found, dir_ / kLightGlueWeights);
}

TEST_F(ModelFiles, ConfiguredPathMustExist) {
  EXPECT_THROW(find_weights(dir_ / "missing.safetensors", superpoint_weight_names()), InputError);
  EXPECT_THROW(find_weights(dir_, superpoint_weight_names()), InputError);  // folder without the files
  touch(kPllvoSuperPointWeights);
  EXPECT_EQ(find_weights(dir_, superpoint_weight_names()).found, dir_ / kPllvoSuperPointWeights);
  touch("mine.safetensors");
  EXPECT_EQ(find_weights(dir_ / "mine.safetensors", superpoint_weight_names()).found, dir_ / "mine.safetensors");
}

}  // namespace
}  // namespace pllvo::nn
