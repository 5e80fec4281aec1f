#include <gtest/gtest.h>

#include "pllvo/common/error.h"
#include "pllvo/vo/keyframe_matcher.h"

namespace pllvo::vo {
namespace {

/// Features at x = 0, 1, 2, ... whose one-column descriptor is the x value.
PointFeatures row_of_features(int n) {
  PointFeatures f;
  f.descriptors.create(n, 1, CV_32F);
  for (int i = 0; i < n; ++i) {
    f.points.emplace_back(static_cast<float>(i), 0.0f);
    f.scores.push_back(0.5f);
    f.source.push_back(-1);
    f.descriptors.at<float>(i, 0) = static_cast<float>(i);
  }
  return f;
}

/// Matches equal descriptors and records what it was given.
class EqualDescriptorMatcher final : public KeyframeMatcher {
 public:
  std::string name() const override { return "equal"; }
  std::vector<PointMatch> match(const PointFeatures& a, const PointFeatures& b, cv::Size) override {
    seen_a = a.size(), seen_b = b.size();
    std::vector<PointMatch> out;
    for (int i = 0; i < static_cast<int>(a.size()); ++i)
      for (int j = 0; j < static_cast<int>(b.size()); ++j)
        if (a.descriptors.at<float>(i, 0) == b.descriptors.at<float>(j, 0)) out.push_back({i, j, 1.0f});
    return out;
  }
  size_t seen_a = 0, seen_b = 0;
};

TEST(PointFeaturesSelect, KeepsTheRowsAskedForInOrder) {
  const PointFeatures f = row_of_features(5);
  const PointFeatures s = f.select({3, 1});
  ASSERT_EQ(s.size(), 2u);
  EXPECT_FLOAT_EQ(s.points[0].x, 3.0f);
  EXPECT_FLOAT_EQ(s.points[1].x, 1.0f);
  EXPECT_FLOAT_EQ(s.descriptors.at<float>(0, 0), 3.0f);
  EXPECT_FLOAT_EQ(s.descriptors.at<float>(1, 0), 1.0f);
  EXPECT_EQ(s.scores.size(), 2u);
  EXPECT_EQ(s.source.size(), 2u);
  EXPECT_EQ(f.select({}).size(), 0u);
}

TEST(MatchUnflagged, MatchesOnlyUnflaggedRowsAndIndexesTheFullSets) {
  const PointFeatures a = row_of_features(6), b = row_of_features(6);
  EqualDescriptorMatcher matcher;
  // Rows 0 and 2 of a and row 4 of b are already linked (by KLT in the pipeline).
  const std::vector<char> skip_a{1, 0, 1, 0, 0, 0}, skip_b{0, 0, 0, 0, 1, 0};
  const auto matches = match_unflagged(matcher, a, skip_a, b, skip_b, {640, 480});
  EXPECT_EQ(matcher.seen_a, 4u);
  EXPECT_EQ(matcher.seen_b, 5u);
  // Equal descriptors in both unflagged sets: 1, 3 and 5 (0 and 2 skipped in a, 4 in b).
  ASSERT_EQ(matches.size(), 3u);
  for (const auto& m : matches) {
    EXPECT_EQ(m.a, m.b) << "indices must refer to the full sets";
    EXPECT_FALSE(skip_a[static_cast<size_t>(m.a)]);
    EXPECT_FALSE(skip_b[static_cast<size_t>(m.b)]);
  }
  EXPECT_EQ(matches[0].a, 1);
  EXPECT_EQ(matches[1].a, 3);
  EXPECT_EQ(matches[2].a, 5);
}

TEST(MatchUnflagged, RejectsFlagsThatDoNotFitTheFeatures) {
  const PointFeatures a = row_of_features(3), b = row_of_features(3);
  EqualDescriptorMatcher matcher;
  EXPECT_THROW(match_unflagged(matcher, a, {0, 0}, b, {0, 0, 0}, {640, 480}), InternalError);
}

}  // namespace
}  // namespace pllvo::vo
