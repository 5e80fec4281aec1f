// Mutual nearest neighbours: mutual check, ratio test and distance threshold on descriptors
// whose answers are known.
#include <gtest/gtest.h>

#include <cmath>

#include "pllvo/common/error.h"
#include "pllvo/nn/mnn_matcher.h"

namespace pllvo::nn {
namespace {

Features features(const std::vector<std::vector<float>>& rows) {
  Features f;
  f.descriptors.resize(static_cast<Eigen::Index>(rows.size()), 4);
  for (std::size_t i = 0; i < rows.size(); ++i)
    f.descriptors.row(static_cast<Eigen::Index>(i)) = Eigen::Vector4f(rows[i].data()).normalized().transpose();
  f.keypoints = KeypointMatrix::Zero(f.descriptors.rows(), 2);
  f.image_size = {64, 64};
  return f;
}

TEST(MutualNearestNeighbours, MutualCheckRatioTestAndDistance) {
  // Image 0: a = e0, b = e1, c = mostly e2, d = mostly e3.
  // Image 1: u, w = e1 tilted by +-0.3 towards e0 (equally near b), e0, e0 + e3, e3.
  const Features f0 = features({{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0.1f}, {0.1f, 0, 0, 1}});
  const Features f1 = features({{0.3f, 1, 0, 0}, {1, 0, 0, 0}, {0.7f, 0, 0, 0.7f}, {0, 0, 0, 1}, {-0.3f, 1, 0, 0}});
  MnnConfig config;
  config.distance_threshold = 0;  // off
  auto m = match_mutual_nearest(f0, f1, config);
  // a-e0, b-u (tie with w: the first index wins), d-e3; c's nearest (e3) prefers d.
  ASSERT_EQ(m.size(), 3);
  EXPECT_EQ(m.pairs.row(0), Eigen::RowVector2i(0, 1));
  EXPECT_EQ(m.pairs.row(1), Eigen::RowVector2i(1, 0));
  EXPECT_EQ(m.pairs.row(2), Eigen::RowVector2i(3, 3));
  EXPECT_NEAR(m.scores(0), 1.0f, 1e-6f);
  EXPECT_NEAR(m.scores(1), 1.0f / std::sqrt(1.09f), 1e-6f);

  config.mutual = false;  // c keeps its nearest neighbour e3
  m = match_mutual_nearest(f0, f1, config);
  ASSERT_EQ(m.size(), 4);
  EXPECT_EQ(m.pairs.row(2), Eigen::RowVector2i(2, 3));

  config.mutual = true;
  config.ratio_threshold = 0.8f;  // b's two nearest are equally far: ambiguous, rejected
  m = match_mutual_nearest(f0, f1, config);
  ASSERT_EQ(m.size(), 2);
  EXPECT_EQ(m.pairs.row(1), Eigen::RowVector2i(3, 3));

  config.ratio_threshold = 0;
  config.distance_threshold = 0.1f;  // b-u is 0.29 apart, d-e3 0.0996: only b goes
  EXPECT_EQ(match_mutual_nearest(f0, f1, config).size(), 2);
  config.distance_threshold = 0.09f;  // now d goes too
  EXPECT_EQ(match_mutual_nearest(f0, f1, config).size(), 1);
}

TEST(MutualNearestNeighbours, EmptyAndMismatchedInputs) {
  const Features f0 = features({{1, 0, 0, 0}});
  Features empty;
  empty.descriptors.resize(0, 4);
  EXPECT_EQ(match_mutual_nearest(f0, empty, {}).size(), 0);
  Features other = f0;
  other.descriptors = DescriptorMatrix::Ones(1, 8);
  EXPECT_THROW(match_mutual_nearest(f0, other, {}), InputError);
}

}  // namespace
}  // namespace pllvo::nn
