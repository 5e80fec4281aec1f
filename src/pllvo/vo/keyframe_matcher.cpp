#include "pllvo/vo/keyframe_matcher.h"

#include <opencv2/features2d.hpp>

#include "pllvo/common/error.h"

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

// INTERIM (until nn/ lands with its MNN and LightGlue): mutual nearest neighbour in L2 via
// cv::BFMatcher's cross check.
class MutualNearestMatcher final : public KeyframeMatcher {
 public:
  explicit MutualNearestMatcher(const MappingConfig& c) : max_distance_(c.mnn_max_distance) {}
  std::string name() const override { return "mnn"; }
  std::vector<PointMatch> match(const PointFeatures& a, const PointFeatures& b, cv::Size) override {
    std::vector<PointMatch> out;
    if (a.empty() || b.empty()) return out;
    cv::BFMatcher bf(a.binary() ? cv::NORM_HAMMING : cv::NORM_L2, true);
    std::vector<cv::DMatch> matches;
    bf.match(a.descriptors, b.descriptors, matches);
    for (const auto& m : matches)
      if (a.binary() || m.distance <= max_distance_) out.push_back({m.queryIdx, m.trainIdx, m.distance});
    return out;
  }

 private:
  double max_distance_;
};

}  // namespace

std::unique_ptr<KeyframeMatcher> make_keyframe_matcher(const MappingConfig& config, const std::string& frontend) {
  if (frontend == "orb" || frontend == "shitomasi") return std::make_unique<HammingRatioMatcher>(config);
  if (config.matcher == "lightglue")
    throw InputError("matcher 'lightglue' is not available in this build yet (the nn module has not landed)");
  return std::make_unique<MutualNearestMatcher>(config);
}

}  // namespace pllvo::vo
