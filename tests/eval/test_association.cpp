#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "pllvo/eval/association.h"
#include "pllvo/eval/eval_error.h"

using namespace pllvo::eval;

namespace {

/// evo's rule written out directly: full scan, first index on ties.
Association brute_force(const std::vector<double>& ref, const std::vector<double>& est, const AssociationOptions& o) {
  Association a;
  a.est_longer_than_ref = est.size() > ref.size();
  const auto& s = a.est_longer_than_ref ? ref : est;
  const auto& l = a.est_longer_than_ref ? est : ref;
  const double shift = a.est_longer_than_ref ? o.t_offset : -o.t_offset;
  for (size_t i = 0; i < s.size(); ++i) {
    size_t best = 0;
    for (size_t j = 1; j < l.size(); ++j)
      if (std::abs((l[j] + shift) - s[i]) < std::abs((l[best] + shift) - s[i])) best = j;
    if (std::abs((l[best] + shift) - s[i]) > o.t_max_diff) continue;
    a.ref_indices.push_back(a.est_longer_than_ref ? i : best);
    a.est_indices.push_back(a.est_longer_than_ref ? best : i);
  }
  return a;
}

}  // namespace

TEST(Association, OffsetMovesTheEstimateWhicheverSideIsLonger) {
  const std::vector<double> ref{10.0, 10.1, 10.2, 10.3};
  const std::vector<double> est_short{9.9, 10.1};  // est + 0.1 = ref
  const std::vector<double> est_long{9.9, 9.95, 10.0, 10.1, 10.2};
  const AssociationOptions o{0.01, 0.1};
  const auto a = associate(ref, est_short, o);
  EXPECT_FALSE(a.est_longer_than_ref);
  EXPECT_EQ(a.ref_indices, (std::vector<size_t>{0, 2}));
  EXPECT_EQ(a.est_indices, (std::vector<size_t>{0, 1}));
  const auto b = associate(ref, est_long, o);
  EXPECT_TRUE(b.est_longer_than_ref);
  EXPECT_EQ(b.ref_indices, (std::vector<size_t>{0, 1, 2, 3}));
  EXPECT_EQ(b.est_indices, (std::vector<size_t>{0, 2, 3, 4}));
}

TEST(Association, EqualLengthSearchesTheReferenceAndAllowsRepeats) {
  // Equal length: the estimate is the short side; two estimate stamps may take the same ref.
  const std::vector<double> ref{0.0, 1.0, 2.0};
  const std::vector<double> est{0.98, 1.02, 5.0};
  const auto a = associate(ref, est, {0.05, 0.0});
  EXPECT_FALSE(a.est_longer_than_ref);
  EXPECT_EQ(a.ref_indices, (std::vector<size_t>{1, 1}));
  EXPECT_EQ(a.est_indices, (std::vector<size_t>{0, 1}));
}

TEST(Association, ThresholdIsInclusive) {
  const auto a = associate({0.0, 1.0, 2.0}, {0.5, 1.25, 2.5}, {0.25, 0.0});  // exact binary fractions
  EXPECT_EQ(a.est_indices, (std::vector<size_t>{1}));
  EXPECT_EQ(a.ref_indices, (std::vector<size_t>{1}));
}

TEST(Association, NoMatchIsSyncError) {
  try {
    associate({0.0, 1.0}, {5.0, 6.0}, {0.01, 0.0});
    FAIL() << "no error";
  } catch (const EvalError& e) {
    EXPECT_EQ(e.kind(), EvalErrorKind::sync);
    EXPECT_EQ(std::string(e.what()),
              "found no matching timestamps between reference and estimate with max. time diff 0.01 (s) and "
              "time offset 0.0 (s)");
  }
}

// The binary search on sorted stamps must pick exactly what the full scan picks, ties included
// (stamps on a coarse grid make equal distances common), and unsorted stamps use the scan.
TEST(Association, SortedSearchEqualsFullScan) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> grid(0, 400);
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<double> ref(1 + trial % 37), est(1 + (trial * 7) % 41);
    for (auto& t : ref) t = 1403636580.0 + 0.005 * grid(rng);
    for (auto& t : est) t = 1403636580.0 + 0.005 * grid(rng);
    if (trial % 4 != 0) {
      std::sort(ref.begin(), ref.end());
      std::sort(est.begin(), est.end());
    }
    const AssociationOptions o{0.005 * (trial % 5), 0.005 * (trial % 3) - 0.005};
    const auto expected = brute_force(ref, est, o);
    if (expected.size() == 0) continue;
    const auto got = associate(ref, est, o);
    EXPECT_EQ(got.ref_indices, expected.ref_indices) << "trial " << trial;
    EXPECT_EQ(got.est_indices, expected.est_indices) << "trial " << trial;
  }
}
