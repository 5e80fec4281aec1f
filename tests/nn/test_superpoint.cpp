// SuperPoint against the official reference vectors (testvectors/superpoint/README.md):
// dense maps, keypoints (same set, same order up to score ties), scores and descriptors.
#include <gtest/gtest.h>

#include <map>
#include <set>

#include <opencv2/imgcodecs.hpp>

#include "nn_test_util.h"
#include "pllvo/common/error.h"
#include "pllvo/nn/superpoint.h"

namespace pllvo::nn {
namespace {

using test::max_abs_diff;
using test::superpoint_vector;

const SuperPoint& random_superpoint() {
  static const SuperPoint net(SafeTensors::load(superpoint_vector("superpoint_random_weights.safetensors")), {});
  return net;
}

// The network runs once per image for all tests.
const SuperPointDense& dense_output(const std::string& image) {
  static std::map<std::string, SuperPointDense> cache;
  auto it = cache.find(image);
  if (it == cache.end()) {
    const cv::Mat img = cv::imread(superpoint_vector(image + ".png").string(), cv::IMREAD_GRAYSCALE);
    it = cache.emplace(image, random_superpoint().run_network(img)).first;
  }
  return it->second;
}

class SuperPointDenseVector : public ::testing::TestWithParam<std::string> {};

TEST_P(SuperPointDenseVector, ScoreMapAndDescriptorMapMatchOfficialCode) {
  const auto ref = SafeTensors::load(superpoint_vector(GetParam() + "_dense.safetensors"));
  const auto& dense = dense_output(GetParam());
  const auto& shape = ref.at("scores_dense").shape;
  ASSERT_EQ(dense.scores.rows(), shape[0]);
  ASSERT_EQ(dense.scores.cols(), shape[1]);
  const auto scores = ref.floats("scores_dense");
  const double score_err = max_abs_diff(scores, dense.scores.data(), static_cast<std::size_t>(dense.scores.size()));
  EXPECT_LE(score_err, 1e-4);

  const auto channels = ref.ints("descriptors_dense_channels");
  const auto sub = ref.floats("descriptors_dense_sub");
  const auto& sub_shape = ref.at("descriptors_dense_sub").shape;  // [8, h, w]
  ASSERT_EQ(sub_shape[1], dense.cells_h);
  ASSERT_EQ(sub_shape[2], dense.cells_w);
  double desc_err = 0;
  const std::size_t cells = static_cast<std::size_t>(dense.cells_h * dense.cells_w);
  for (std::size_t k = 0; k < channels.size(); ++k)
    for (std::size_t cell = 0; cell < cells; ++cell)
      desc_err = std::max(desc_err, std::abs(double(sub[k * cells + cell]) -
                                             dense.descriptors(static_cast<Eigen::Index>(cell), channels[k])));
  EXPECT_LE(desc_err, 1e-4);
  RecordProperty("scores_dense_max_abs", test::sci(score_err));
  RecordProperty("descriptors_dense_max_abs", test::sci(desc_err));
}

INSTANTIATE_TEST_SUITE_P(Official, SuperPointDenseVector,
                         ::testing::Values("icl250_640x480", "sacre_coeur1_752x480", "sacre_coeur2_752x480"));

struct KeypointCase {
  std::string image;
  std::string config;  // kall | k512
  friend void PrintTo(const KeypointCase& c, std::ostream* os) { *os << c.image << "_" << c.config; }
};

class SuperPointKeypointVector : public ::testing::TestWithParam<KeypointCase> {};

// Two keypoints whose official scores differ by less than this may come out in either order:
// the softmax's last bits depend on the CPU's convolution kernels (seen: 1.05e-8 apart on an AMD
// EPYC, sacre_coeur1 k512 ranks 407/408, swapped there by PyTorch too).
constexpr float kScoreTie = 1e-7f;

/// For each of our keypoints, its index in the reference; a failure (and an empty result) when
/// the sets differ or the order differs by more than a tie.
std::vector<int> order_within_ties(const std::vector<float>& ref_kp, const std::vector<float>& ref_scores,
                                   const Features& f) {
  std::map<std::pair<float, float>, int> where;
  for (std::size_t j = 0; j < ref_scores.size(); ++j) where[{ref_kp[2 * j], ref_kp[2 * j + 1]}] = static_cast<int>(j);
  std::vector<int> order;
  std::set<int> used;
  for (int i = 0; i < f.size(); ++i) {
    const auto it = where.find({static_cast<float>(f.keypoints(i, 0)), static_cast<float>(f.keypoints(i, 1))});
    if (it == where.end()) {
      ADD_FAILURE() << "keypoint " << i << " (" << f.keypoints(i, 0) << ", " << f.keypoints(i, 1)
                    << ") is not in the reference";
      return {};
    }
    const int j = it->second;
    const float gap = std::abs(ref_scores[static_cast<std::size_t>(i)] - ref_scores[static_cast<std::size_t>(j)]);
    if (gap > kScoreTie || !used.insert(j).second) {
      ADD_FAILURE() << "keypoint " << i << " is the reference's " << j << ", whose score differs by " << gap;
      return {};
    }
    order.push_back(j);
  }
  return order;
}

TEST_P(SuperPointKeypointVector, KeypointsInOrderScoresAndDescriptorsMatchOfficialCode) {
  const auto& c = GetParam();
  const auto ref = SafeTensors::load(superpoint_vector(c.image + "_" + c.config + ".safetensors"));
  const auto& dense = dense_output(c.image);
  const auto& config = random_superpoint().config();
  const int max_keypoints = c.config == "k512" ? 512 : -1;
  const auto candidates = find_candidates(dense.scores, config.nms_radius, config.remove_borders);
  const Features f = extract_features(dense, candidates, select_keypoints(candidates, 0.0005f, max_keypoints));

  const auto kp = ref.floats("keypoints");
  const auto ref_scores = ref.floats("keypoint_scores");
  ASSERT_EQ(static_cast<std::size_t>(f.size()) * 2, kp.size()) << "keypoint count differs";
  const std::vector<int> order = order_within_ties(kp, ref_scores, f);
  ASSERT_EQ(order.size(), static_cast<std::size_t>(f.size()));
  const auto ref_desc = ref.floats("descriptors");
  const std::size_t dim = ref_desc.size() / order.size();
  std::vector<float> scores_in_our_order, desc_in_our_order;
  for (const int j : order) {
    scores_in_our_order.push_back(ref_scores[static_cast<std::size_t>(j)]);
    desc_in_our_order.insert(desc_in_our_order.end(), ref_desc.begin() + static_cast<std::ptrdiff_t>(j * dim),
                             ref_desc.begin() + static_cast<std::ptrdiff_t>((j + 1) * dim));
  }
  const double score_err = max_abs_diff(scores_in_our_order, f.scores.data(), f.scores.size());
  const double desc_err = max_abs_diff(desc_in_our_order, f.descriptors.data(), f.descriptors.size());
  EXPECT_LE(score_err, 1e-5);
  EXPECT_LE(desc_err, 1e-4);
  RecordProperty("keypoints", f.size());
  RecordProperty("keypoint_scores_max_abs", test::sci(score_err));
  RecordProperty("descriptors_max_abs", test::sci(desc_err));
  const auto size = ref.ints("image_size");
  EXPECT_EQ(f.image_size.x(), size[0]);
  EXPECT_EQ(f.image_size.y(), size[1]);
}

INSTANTIATE_TEST_SUITE_P(Official, SuperPointKeypointVector,
                         ::testing::Values(KeypointCase{"icl250_640x480", "kall"}, KeypointCase{"icl250_640x480", "k512"},
                                           KeypointCase{"icl254_640x480", "k512"},
                                           KeypointCase{"sacre_coeur1_752x480", "kall"},
                                           KeypointCase{"sacre_coeur1_752x480", "k512"},
                                           KeypointCase{"sacre_coeur2_752x480", "kall"}),
                         [](const auto& info) { return info.param.image + "_" + info.param.config; });

TEST(SuperPoint, DetectAppliesThresholdAndTopK) {
  const cv::Mat img = cv::imread(superpoint_vector("icl250_640x480.png").string(), cv::IMREAD_GRAYSCALE);
  const auto all = random_superpoint().detect(img);  // default config = kall
  const auto ref = SafeTensors::load(superpoint_vector("icl250_640x480_kall.safetensors"));
  EXPECT_EQ(all.size(), ref.at("keypoints").shape[0]);
  const auto top = random_superpoint().detect(img, 0.0005f, 100);
  ASSERT_EQ(top.size(), 100);
  for (int i = 1; i < top.size(); ++i) EXPECT_GE(top.scores(i - 1), top.scores(i));
  EXPECT_EQ(top.scores(0), all.scores.maxCoeff());
}

TEST(SuperPoint, DownscaledInputMapsKeypointsBackToFullResolution) {
  const cv::Mat img = cv::imread(superpoint_vector("sacre_coeur1_752x480.png").string(), cv::IMREAD_GRAYSCALE);
  SuperPointConfig config;
  config.downscale = 2.0;
  const SuperPoint half(SafeTensors::load(superpoint_vector("superpoint_random_weights.safetensors")), config);
  const auto f = half.detect(img);
  ASSERT_GT(f.size(), 20);
  EXPECT_EQ(f.image_size, Eigen::Vector2i(752, 480));
  // Network pixel k maps to 2k + 0.5: on the full-resolution grid shifted by half a pixel.
  for (int i = 0; i < f.size(); ++i) {
    const float x = f.keypoints(i, 0), y = f.keypoints(i, 1);
    EXPECT_FLOAT_EQ(std::fmod(x - 0.5f, 2.0f), 0.0f);
    EXPECT_FLOAT_EQ(std::fmod(y - 0.5f, 2.0f), 0.0f);
    EXPECT_GE(x, 8.5f);
    EXPECT_LE(x, 752 - 9.5f);
  }
}

TEST(SuperPoint, RejectsColourImages) {
  const cv::Mat colour(64, 64, CV_8UC3, cv::Scalar(1, 2, 3));
  EXPECT_THROW(random_superpoint().run_network(colour), InputError);
}

TEST(SuperPoint, WeightErrorsNameTheTensor) {
  auto st = SafeTensors::load(superpoint_vector("superpoint_random_weights.safetensors"));
  auto broken = st;
  broken.erase("convPa.bias");
  try {
    SuperPoint net(broken, {});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "convPa.bias");
  }
  broken = st;
  const std::vector<float> wrong(64 * 3 * 3 * 3, 0.0f);
  broken.set_f32("conv1a.weight", {64, 3, 3, 3}, wrong.data());
  try {
    SuperPoint net(broken, {});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "conv1a.weight");
    EXPECT_NE(std::string(e.what()).find("[64, 1, 3, 3]"), std::string::npos) << e.what();
  }
  broken = st;
  broken.set_f32("extra.weight", {1}, wrong.data());
  EXPECT_THROW(SuperPoint(broken, {}), InputError);
}

}  // namespace
}  // namespace pllvo::nn
