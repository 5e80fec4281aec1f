#include "pllvo/vo/keyframe_matcher.h"

#include <algorithm>

#include <opencv2/features2d.hpp>

#include "pllvo/common/error.h"
#include "pllvo/nn/matcher.h"
#include "pllvo/nn/model_files.h"

namespace pllvo::vo {
namespace {

/// Brute-force Hamming matching with Lowe's ratio test, then one-to-one by distance.
class HammingRatioMatcher final : public KeyframeMatcher {
 public:
  explicit HammingRatioMatcher(const MappingConfig& c) : ratio_(c.orb_ratio), max_distance_(c.orb_max_hamming) {}
  std::string name() const override { return "hamming-ratio"; }
  std::vector<PointMatch> match(const PointFeatures& a, const PointFeatures& b, cv::Size) override {
    std::vector<PointMatch> out;
    if (a.size() < 2 || b.size() < 2) return out;
    cv::BFMatcher bf(cv::NORM_HAMMING);
    std::vector<std::vector<cv::DMatch>> knn;
    bf.knnMatch(a.descriptors, b.descriptors, knn, 2);
    std::vector<int> best_for_b(b.size(), -1);
    std::vector<float> best_dist(b.size(), 1e9f);
    for (const auto& m : knn) {
      if (m.size() < 2 || m[0].distance > max_distance_ || m[0].distance >= ratio_ * m[1].distance) continue;
      if (m[0].distance < best_dist[m[0].trainIdx]) {
        best_dist[m[0].trainIdx] = m[0].distance;
        best_for_b[m[0].trainIdx] = m[0].queryIdx;
      }
    }
    for (size_t j = 0; j < b.size(); ++j)
      if (best_for_b[j] >= 0) out.push_back({best_for_b[j], static_cast<int>(j), best_dist[j]});
    return out;
  }

 private:
  double ratio_;
  int max_distance_;
};

/// Binary descriptors, mapping.matcher: mnn: mutual nearest neighbours in Hamming distance.
class HammingMutualMatcher final : public KeyframeMatcher {
 public:
  explicit HammingMutualMatcher(const MappingConfig& c) : max_distance_(c.orb_max_hamming) {}
  std::string name() const override { return "hamming-mnn"; }
  std::vector<PointMatch> match(const PointFeatures& a, const PointFeatures& b, cv::Size) override {
    std::vector<PointMatch> out;
    if (a.empty() || b.empty()) return out;
    cv::BFMatcher bf(cv::NORM_HAMMING, true);
    std::vector<cv::DMatch> matches;
    bf.match(a.descriptors, b.descriptors, matches);
    for (const auto& m : matches)
      if (m.distance <= max_distance_) out.push_back({m.queryIdx, m.trainIdx, m.distance});
    return out;
  }

 private:
  int max_distance_;
};

nn::Features to_nn(const PointFeatures& f, cv::Size image_size) {
  nn::Features out;
  const auto n = static_cast<Eigen::Index>(f.size());
  out.keypoints.resize(n, 2);
  out.scores.resize(n);
  out.descriptors.resize(n, f.descriptors.cols);
  for (Eigen::Index i = 0; i < n; ++i) {
    out.keypoints(i, 0) = f.points[i].x;
    out.keypoints(i, 1) = f.points[i].y;
    out.scores(i) = f.scores.empty() ? 1.0f : f.scores[i];
    std::copy_n(f.descriptors.ptr<float>(static_cast<int>(i)), f.descriptors.cols, out.descriptors.row(i).data());
  }
  out.image_size = {image_size.width, image_size.height};
  return out;
}

/// Float descriptors (SuperPoint): nn's LightGlue or mutual nearest neighbours.
class NeuralMatcher final : public KeyframeMatcher {
 public:
  explicit NeuralMatcher(std::unique_ptr<nn::FeatureMatcher> matcher) : matcher_(std::move(matcher)) {}
  std::string name() const override { return matcher_->name(); }
  std::vector<PointMatch> match(const PointFeatures& a, const PointFeatures& b, cv::Size image_size) override {
    std::vector<PointMatch> out;
    if (a.empty() || b.empty()) return out;
    if (a.binary() || b.binary()) throw InternalError("keyframe matcher: SuperPoint matching needs float descriptors");
    const nn::Matches m = matcher_->match(to_nn(a, image_size), to_nn(b, image_size));
    if (m.layers_run > 0) last_effort_ = MatchEffort{m.layers_run, m.pruned_share};
    out.reserve(static_cast<size_t>(m.size()));
    for (int k = 0; k < m.size(); ++k) out.push_back({m.pairs(k, 0), m.pairs(k, 1), m.scores(k)});
    return out;
  }
  std::optional<MatchEffort> last_effort() const override { return last_effort_; }

 private:
  std::unique_ptr<nn::FeatureMatcher> matcher_;
  std::optional<MatchEffort> last_effort_;
};

}  // namespace

std::vector<PointMatch> match_unflagged(KeyframeMatcher& matcher, const PointFeatures& a, const std::vector<char>& skip_a,
                                        const PointFeatures& b, const std::vector<char>& skip_b, cv::Size image_size) {
  if (skip_a.size() != a.size() || skip_b.size() != b.size())
    throw InternalError("match_unflagged: one flag per feature expected");
  auto unflagged = [](const std::vector<char>& skip) {
    std::vector<int> rows;
    for (size_t i = 0; i < skip.size(); ++i)
      if (!skip[i]) rows.push_back(static_cast<int>(i));
    return rows;
  };
  const std::vector<int> rows_a = unflagged(skip_a), rows_b = unflagged(skip_b);
  std::vector<PointMatch> matches = matcher.match(a.select(rows_a), b.select(rows_b), image_size);
  for (auto& m : matches) m.a = rows_a.at(static_cast<size_t>(m.a)), m.b = rows_b.at(static_cast<size_t>(m.b));
  return matches;
}

std::unique_ptr<KeyframeMatcher> make_keyframe_matcher(const MappingConfig& config, const std::string& frontend) {
  if (frontend == "orb" || frontend == "shitomasi") {
    if (config.matcher == "lightglue")
      throw InputError("mapping.matcher 'lightglue' needs SuperPoint descriptors (frontend.type superpoint); the '" +
                       frontend + "' front end matches with 'auto' (Hamming + ratio test) or 'mnn'");
    if (config.matcher == "mnn") return std::make_unique<HammingMutualMatcher>(config);
    return std::make_unique<HammingRatioMatcher>(config);
  }
  nn::MatcherConfig mc;
  mc.type = config.matcher == "mnn" ? "mnn" : "lightglue";
  mc.lightglue.weights = config.lightglue_weights;
  mc.lightglue.depth_confidence = static_cast<float>(config.lightglue_depth_confidence);
  mc.lightglue.width_confidence = static_cast<float>(config.lightglue_width_confidence);
  mc.mnn.distance_threshold = static_cast<float>(config.mnn_max_distance);
  if (config.matcher == "lightglue") {
    // Asked for by name (an ablation, a benchmark): no silent fallback.
    const auto search = nn::find_weights(config.lightglue_weights, nn::lightglue_weight_names());
    if (!search.found)
      throw InputError("mapping.matcher is 'lightglue' but LightGlue weights were " + search.not_found_message() +
                       "; use 'auto' to fall back to 'mnn'");
  }
  std::string notice;  // auto without weights: nn logs the fallback to mutual nearest neighbours
  return std::make_unique<NeuralMatcher>(nn::make_matcher(mc, &notice));
}

}  // namespace pllvo::vo
