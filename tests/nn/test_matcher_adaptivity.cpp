// The matcher interface reports LightGlue's adaptivity (layers run, share of points pruned), which the
// VO's statistics and `pllvo bench` show; mutual nearest neighbour reports none.
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include "nn_test_util.h"
#include "pllvo/nn/lightglue.h"
#include "pllvo/nn/matcher.h"
#include "pllvo/nn/superpoint.h"

namespace pllvo::nn {
namespace {

using test::superpoint_vector;

TEST(MatcherAdaptivity, LightGlueReportsLayersRunAndPrunedShare) {
  SuperPointConfig sp_config;  // pllvo's shipped weights (models/)
  sp_config.downscale = 2.0;
  const SuperPoint superpoint(sp_config);
  const auto f0 = superpoint.detect(cv::imread(superpoint_vector("icl250_640x480.png").string(), cv::IMREAD_GRAYSCALE));
  const auto f1 = superpoint.detect(cv::imread(superpoint_vector("icl254_640x480.png").string(), cv::IMREAD_GRAYSCALE));
  ASSERT_GT(f0.size(), 100);

  MatcherConfig config;  // lightglue, pllvo's shipped weights
  const auto matcher = make_matcher(config);
  ASSERT_EQ(matcher->name(), "lightglue");
  const auto matches = matcher->match(f0, f1);

  const LightGlue lightglue{LightGlueConfig{}};
  const auto reference = lightglue.match(f0, f1);
  EXPECT_GT(matches.size(), 50);
  EXPECT_EQ(matches.layers_run, reference.stop);
  EXPECT_GE(matches.layers_run, 1);
  EXPECT_LE(matches.layers_run, lightglue.architecture().n_layers);
  const auto pruned = (reference.prune0.array() < reference.stop).count() + (reference.prune1.array() < reference.stop).count();
  EXPECT_FLOAT_EQ(matches.pruned_share, static_cast<float>(pruned) / static_cast<float>(f0.size() + f1.size()));

  config.type = "mnn";
  const auto mnn = make_matcher(config)->match(f0, f1);
  EXPECT_EQ(mnn.layers_run, 0);
  EXPECT_EQ(mnn.pruned_share, 0.0f);
}

}  // namespace
}  // namespace pllvo::nn
