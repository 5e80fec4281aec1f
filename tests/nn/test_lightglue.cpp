// LightGlue against the official reference vectors (testvectors/lightglue/README.md): all
// three settings (a: 9 layers, no adaptivity; b: early exit + pruning; c: 3 layers, d=64 with
// input projection) on both pairs. Integer outputs must be identical.
#include <gtest/gtest.h>

#include <map>
#include <nlohmann/json.hpp>

#include "nn_test_util.h"
#include "pllvo/common/error.h"
#include "pllvo/nn/lightglue.h"
#include "pllvo/nn/runtime.h"

namespace pllvo::nn {
namespace {

using test::lightglue_vector;
using test::max_abs_diff;

struct Case {
  char setting;   // a | b | c
  char pair;      // A | B
  int threads;    // 2: each image's half of every layer on its own thread (nn::TwoLanes)
  friend void PrintTo(const Case& c, std::ostream* os) { *os << c.setting << "_pair" << c.pair << "_" << c.threads << "threads"; }
};

std::string vector_name(const Case& c) { return std::string(1, c.setting) + "_pair" + c.pair + ".safetensors"; }

const LightGlue& model(char setting, const LightGlueConfig& config) {
  static std::map<char, LightGlue> cache;
  auto it = cache.find(setting);
  if (it == cache.end()) {
    SafeTensors w = setting == 'c'
                        ? SafeTensors::load(lightglue_vector("lightglue_random_l3_d64.safetensors"))
                        : load_weights_with_overrides(
                              lightglue_vector("lightglue_sp_random_l9_d256.safetensors"),
                              setting == 'b' ? std::vector<std::filesystem::path>{lightglue_vector(
                                                   "lightglue_sp_random_l9_d256_b_token_confidence.safetensors")}
                                             : std::vector<std::filesystem::path>{});
    it = cache.emplace(setting, LightGlue(w, config)).first;
  }
  return it->second;
}

// The official configuration stored in the vector's metadata.
LightGlueConfig config_of(const SafeTensors& ref) {
  const auto conf = nlohmann::json::parse(ref.metadata().at("conf"));
  LightGlueConfig c;
  c.depth_confidence = conf["depth_confidence"].get<float>();
  c.width_confidence = conf["width_confidence"].get<float>();
  c.filter_threshold = conf["filter_threshold"].get<float>();
  c.pruning_keypoint_threshold = -1;  // official CPU rule
  return c;
}

template <typename Vec>
void expect_ints_equal(const std::vector<std::int64_t>& ref, const Vec& ours, const std::string& what) {
  ASSERT_EQ(ref.size(), static_cast<std::size_t>(ours.size())) << what;
  int differ = 0;
  for (std::size_t i = 0; i < ref.size(); ++i) differ += ref[i] != ours(static_cast<Eigen::Index>(i));
  EXPECT_EQ(differ, 0) << what << ": " << differ << " entries differ";
}

class LightGlueVector : public ::testing::TestWithParam<Case> {};

TEST_P(LightGlueVector, ReproducesOfficialOutputs) {
  const Case& c = GetParam();
  const auto ref = SafeTensors::load(lightglue_vector(vector_name(c)));
  const auto f0 = load_features(shared_path("testvectors/" + ref.metadata().at("image0")));
  const auto f1 = load_features(shared_path("testvectors/" + ref.metadata().at("image1")));
  const LightGlueConfig config = config_of(ref);
  const LightGlue& lg = model(c.setting, config);
  ASSERT_EQ(lg.config().depth_confidence, config.depth_confidence);

  struct Threads {  // this test's count, the previous one back afterwards
    int before = num_threads();
    explicit Threads(int n) { set_num_threads(n); }
    ~Threads() { set_num_threads(before); }
  } threads(c.threads);
  LightGlueTrace trace;
  trace.want_log_assignment = true;
  const auto r = lg.match(f0, f1, &trace);

  EXPECT_EQ(r.stop, ref.ints("stop")[0]);
  expect_ints_equal(ref.ints("matches0"), r.matches0, "matches0");
  expect_ints_equal(ref.ints("matches1"), r.matches1, "matches1");
  expect_ints_equal(ref.ints("prune0"), r.prune0, "prune0");
  expect_ints_equal(ref.ints("prune1"), r.prune1, "prune1");
  const auto matches = ref.ints("matches");
  ASSERT_EQ(matches.size(), static_cast<std::size_t>(2 * r.matches.size()));
  for (int k = 0; k < r.matches.size(); ++k) {
    EXPECT_EQ(r.matches.pairs(k, 0), matches[2 * k]);
    EXPECT_EQ(r.matches.pairs(k, 1), matches[2 * k + 1]);
  }
  EXPECT_LE(max_abs_diff(ref.floats("scores"), r.matches.scores.data(), r.matches.scores.size()), 1e-4);
  const double s0 = max_abs_diff(ref.floats("matching_scores0"), r.matching_scores0.data(), r.matching_scores0.size());
  const double s1 = max_abs_diff(ref.floats("matching_scores1"), r.matching_scores1.data(), r.matching_scores1.size());
  EXPECT_LE(s0, 1e-4);
  EXPECT_LE(s1, 1e-4);
  RecordProperty("matching_scores_max_abs", test::sci(std::max(s0, s1)));

  // Log-assignment: full in (a), sampled rows in (c); |diff| <= 1e-3 + 1e-5 |ref|.
  const auto& la = trace.log_assignment;
  double raw = 0;
  const auto check_row = [&](const std::vector<float>& ref_row, Eigen::Index row, double& worst) {
    for (Eigen::Index col = 0; col < la.cols(); ++col) {
      const double rv = ref_row[static_cast<std::size_t>(col)];
      worst = std::max(worst, std::abs(rv - la(row, col)) - 1e-5 * std::abs(rv));
      raw = std::max(raw, std::abs(rv - la(row, col)));
    }
  };
  double worst = 0;
  if (ref.contains("log_assignment")) {
    const auto full = ref.floats("log_assignment");
    ASSERT_EQ(static_cast<std::size_t>(la.size()), full.size());
    for (Eigen::Index row = 0; row < la.rows(); ++row)
      check_row(std::vector<float>(full.begin() + row * la.cols(), full.begin() + (row + 1) * la.cols()), row, worst);
  }
  if (ref.contains("log_assignment_rows")) {
    const auto rows = ref.floats("log_assignment_rows");
    const auto index = ref.ints("log_assignment_row_index");
    for (std::size_t k = 0; k < index.size(); ++k)
      check_row(std::vector<float>(rows.begin() + k * la.cols(), rows.begin() + (k + 1) * la.cols()), index[k], worst);
  }
  EXPECT_LE(worst, 1e-3);
  RecordProperty("log_assignment_excess", test::sci(worst));
  RecordProperty("log_assignment_max_abs", test::sci(raw));
  RecordProperty("matches", r.matches.size());
  RecordProperty("stop", r.stop);

  if (ref.contains("kpts_normalized0")) {
    const KeypointMatrix kn0 = trace.keypoints_normalized0, kn1 = trace.keypoints_normalized1;
    EXPECT_LE(max_abs_diff(ref.floats("kpts_normalized0"), kn0.data(), kn0.size()), 1e-4);
    EXPECT_LE(max_abs_diff(ref.floats("kpts_normalized1"), kn1.data(), kn1.size()), 1e-4);
    const auto check_posenc = [&](const std::string& name, const Eigen::MatrixXf& cos, const Eigen::MatrixXf& sin) {
      const auto pe = ref.floats(name);  // [2, 256, head_dim]: cos then sin of the first 256 points
      const Eigen::Index dh = cos.cols();
      double err = 0;
      for (Eigen::Index i = 0; i < 256; ++i)
        for (Eigen::Index j = 0; j < dh; ++j) {
          err = std::max(err, double(std::abs(pe[i * dh + j] - cos(i, j))));
          err = std::max(err, double(std::abs(pe[(256 + i) * dh + j] - sin(i, j))));
        }
      EXPECT_LE(err, 1e-4) << name;
    };
    check_posenc("posenc0_first256", trace.posenc_cos0, trace.posenc_sin0);
    check_posenc("posenc1_first256", trace.posenc_cos1, trace.posenc_sin1);
    const auto check_desc = [&](const std::string& name, const Eigen::MatrixXf& d) {
      const Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> row_major = d;
      const double err = max_abs_diff(ref.floats(name), row_major.data(), row_major.size());
      EXPECT_LE(err, 1e-4) << name;
      RecordProperty(name + "_max_abs", test::sci(err));
    };
    check_desc("desc0_after_layer0", trace.desc0_after_layer0);
    check_desc("desc1_after_layer0", trace.desc1_after_layer0);
  }
}

INSTANTIATE_TEST_SUITE_P(Official, LightGlueVector,
                         ::testing::Values(Case{'a', 'A', 1}, Case{'a', 'B', 1}, Case{'b', 'A', 1}, Case{'b', 'B', 1},
                                           Case{'c', 'A', 1}, Case{'c', 'B', 1}, Case{'a', 'A', 2}, Case{'b', 'B', 2},
                                           Case{'c', 'A', 2}),
                         [](const auto& info) {
                           return std::string(1, info.param.setting) + "_pair" + info.param.pair +
                                  (info.param.threads == 1 ? "" : "_" + std::to_string(info.param.threads) + "threads");
                         });

TEST(LightGlue, ArchitectureComesFromTheWeights) {
  const auto a = lightglue_architecture(SafeTensors::load(lightglue_vector("lightglue_random_l3_d64.safetensors")));
  EXPECT_EQ(a.input_dim, 256);
  EXPECT_EQ(a.descriptor_dim, 64);
  EXPECT_EQ(a.n_layers, 3);
  EXPECT_EQ(a.num_heads, 4);
  EXPECT_FALSE(a.add_scale_ori);
}

TEST(LightGlue, WeightErrorsNameTheTensor) {
  auto st = SafeTensors::load(lightglue_vector("lightglue_random_l3_d64.safetensors"));
  auto broken = st;
  broken.erase("transformers.1.cross_attn.to_v.bias");
  try {
    LightGlue lg(broken, {});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "transformers.1.cross_attn.to_v.bias");
  }
  broken = st;
  broken.metadata()["config"] = R"({"n_layers": 9})";
  try {
    LightGlue lg(broken, {});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "__metadata__.config.n_layers");
  }
  // confidence_thresholds is optional: recomputed as 0.8 + 0.1 exp(-4 i / n_layers).
  broken = st;
  broken.erase("confidence_thresholds");
  EXPECT_NO_THROW(LightGlue(broken, {}));
}

TEST(LightGlue, ReleasedCheckpointNamesAreRenamedLikeTheOfficialLoader) {
  const auto st = SafeTensors::load(lightglue_vector("lightglue_random_l3_d64.safetensors"));
  SafeTensors released;
  for (const auto& name : st.names()) {
    std::string n = name;
    for (const char* block : {"self_attn", "cross_attn"}) {
      for (int i = 0; i < 3; ++i) {
        const std::string from = "transformers." + std::to_string(i) + "." + block + ".";
        if (n.rfind(from, 0) == 0) n = std::string(block) + "." + std::to_string(i) + "." + n.substr(from.size());
      }
    }
    released.set(n, st.at(name));
  }
  ASSERT_TRUE(released.contains("self_attn.0.Wqkv.weight"));
  const auto f0 = load_features(test::superpoint_vector("icl250_640x480_k512.safetensors"));
  const auto f1 = load_features(test::superpoint_vector("icl254_640x480_k512.safetensors"));
  LightGlueConfig config;
  config.depth_confidence = config.width_confidence = -1;
  const auto a = LightGlue(st, config).match(f0, f1);
  const auto b = LightGlue(released, config).match(f0, f1);
  EXPECT_EQ(a.matches0, b.matches0);
  EXPECT_EQ(a.matches.size(), 21);
}

TEST(LightGlue, EmptyFeatureSetGivesNoMatches) {
  const LightGlue lg(SafeTensors::load(lightglue_vector("lightglue_random_l3_d64.safetensors")), {});
  const auto f0 = load_features(test::superpoint_vector("icl250_640x480_k512.safetensors"));
  Features empty;
  empty.image_size = {640, 480};
  empty.descriptors.resize(0, 256);
  const auto r = lg.match(f0, empty);
  EXPECT_EQ(r.matches.size(), 0);
  EXPECT_EQ(r.matches0.size(), 512);
  EXPECT_EQ((r.matches0.array() == -1).count(), 512);
}

TEST(LightGlue, WrongDescriptorSizeIsAnInputError) {
  const LightGlue lg(SafeTensors::load(lightglue_vector("lightglue_random_l3_d64.safetensors")), {});
  auto f0 = load_features(test::superpoint_vector("icl250_640x480_k512.safetensors"));
  auto f1 = f0;
  f1.descriptors = f1.descriptors.leftCols(128).eval();
  EXPECT_THROW(lg.match(f0, f1), InputError);
  f1 = f0;
  f1.image_size = {0, 0};
  EXPECT_THROW(lg.match(f0, f1), InputError);
}

}  // namespace
}  // namespace pllvo::nn
