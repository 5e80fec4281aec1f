// Every case of ../shared/testvectors/eval/expected.json (computed by evo v1.36.5) must be
// reproduced: counts and indices exactly, floats to max(1e-9, 1e-6 |expected|).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <numbers>
#include <set>
#include <string>

#include <nlohmann/json.hpp>

#include "pllvo/common/fixtures.h"
#include "pllvo/eval/eval_error.h"
#include "pllvo/eval/evaluator.h"
#include "pllvo/eval/trajectory_input.h"
#include "pllvo/geometry/pose.h"

namespace fs = std::filesystem;
using nlohmann::json;
using namespace pllvo::eval;

namespace {

constexpr const char* kFixtureMissing = "fixture_missing";

fs::path vector_dir() { return pllvo::shared_path("testvectors/eval"); }

const json& all_cases() {
  static const json cases = [] {
    std::ifstream in(vector_dir() / "expected.json");
    return json::parse(in);
  }();
  return cases;
}

const json& case_by_id(const std::string& id) {
  static const std::map<std::string, const json*> index = [] {
    std::map<std::string, const json*> m;
    for (const auto& c : all_cases()) m[c.at("id").get<std::string>()] = &c;
    return m;
  }();
  return *index.at(id);
}

/// Case ids for the parameterised test; a missing fixture becomes one failing case.
std::vector<std::string> case_ids() {
  std::vector<std::string> ids;
  try {
    for (const auto& c : all_cases()) ids.push_back(c.at("id").get<std::string>());
  } catch (const std::exception&) {
    ids = {kFixtureMissing};
  }
  return ids;
}

std::string test_name(const testing::TestParamInfo<std::string>& info) {
  std::string name = info.param;
  for (char& ch : name)
    if (ch == '.') ch = 'p';
    else if (ch == '-') ch = 'm';
  return name;
}

bool close(double got, double exp) { return std::abs(got - exp) <= std::max(1e-9, 1e-6 * std::abs(exp)); }

#define EXPECT_CLOSE(got, exp, what)                                                                         \
  do {                                                                                                      \
    const double g_ = (got), e_ = (exp);                                                                    \
    EXPECT_TRUE(close(g_, e_)) << (what) << ": got " << testing::PrintToString(g_) << ", expected "        \
                               << testing::PrintToString(e_) << " (diff " << (g_ - e_) << ")";             \
  } while (0)

EvalOptions options_of(const json& c) {
  const json& o = c.at("options");
  EvalOptions opt;
  opt.min_poses = 1;  // evo's own errors decide in these comparisons
  const bool align = o.at("align"), scale = o.at("correct_scale");
  opt.align = align && scale ? AlignMode::sim3 : align ? AlignMode::se3 : scale ? AlignMode::scale_only : AlignMode::none;
  opt.n_to_align = o.at("n_to_align");
  opt.align_origin = o.at("align_origin");
  if (o.contains("t_max_diff")) opt.association.t_max_diff = o.at("t_max_diff");
  if (o.contains("t_offset")) opt.association.t_offset = o.at("t_offset");
  if (o.contains("delta")) {
    opt.rpe.delta = o.at("delta").get<double>();
    opt.rpe.unit = parse_delta_unit(o.at("delta_unit").get<std::string>());
    opt.rpe.delta_tol = o.at("delta_tol");
    opt.rpe.all_pairs = o.at("all_pairs");
    opt.pairs_from_reference = o.at("pairs_from_reference");
  }
  return opt;
}

/// ref/est index lists of a case, following `identity` and `indices_as_in_case`.
std::pair<std::vector<size_t>, std::vector<size_t>> expected_indices(const json& association) {
  if (association.value("identity", false)) {
    std::vector<size_t> ids(association.at("num_matches").get<size_t>());
    for (size_t i = 0; i < ids.size(); ++i) ids[i] = i;
    return {ids, ids};
  }
  if (association.contains("indices_as_in_case"))
    return expected_indices(case_by_id(association.at("indices_as_in_case")).at("association"));
  return {association.at("ref_indices").get<std::vector<size_t>>(),
          association.at("est_indices").get<std::vector<size_t>>()};
}

/// Smallest distance of any association decision from its threshold: the <= t_max_diff test,
/// and for accepted matches the argmin choice (best vs second-best difference; a rejected
/// best cannot become accepted by the choice). Recomputed from the stamps.
double decision_margin(const pllvo::io::Trajectory& ref, const pllvo::io::Trajectory& est,
                       const AssociationOptions& a) {
  const bool est_long = est.size() > ref.size();
  const auto& s = est_long ? ref.stamps : est.stamps;
  const auto& l = est_long ? est.stamps : ref.stamps;
  const double shift = est_long ? a.t_offset : -a.t_offset;
  double margin = INFINITY;
  for (const double t : s) {
    double best = INFINITY, second = INFINITY;
    for (const double u : l) {
      const double d = std::abs((u + shift) - t);
      if (d < best) {
        second = best;
        best = d;
      } else if (d < second) {
        second = d;
      }
    }
    margin = std::min(margin, std::abs(best - a.t_max_diff));
    if (best <= a.t_max_diff) margin = std::min(margin, second - best);
  }
  return margin;
}

/// Smallest distance of any RPE pair decision from its threshold (metres: the path test, and for
/// all_pairs the tolerance test and the argmin choice; angles: the accumulated or direct angle
/// against its bounds, in rad). Recomputed from the poses the pairs were selected on.
double pair_margin(const PoseList& poses, const PairOptions& o) {
  double margin = INFINITY;
  const double tol = o.delta * o.delta_tol;
  auto step = [&](size_t i) { return (poses[i].translation() - poses[i - 1].translation()).norm(); };
  if (o.unit == DeltaUnit::meters && !o.all_pairs) {
    double path = 0.0;
    for (size_t i = 1; i < poses.size(); ++i) {
      path += step(i);
      margin = std::min(margin, std::abs(path - o.delta));
      if (path >= o.delta) path = 0.0;
    }
  } else if (o.unit == DeltaUnit::meters) {
    std::vector<double> dist(poses.size(), 0.0);
    for (size_t i = 1; i < poses.size(); ++i) dist[i] = dist[i - 1] + step(i);
    for (size_t i = 0; i + 1 < poses.size(); ++i) {
      double best = INFINITY, second = INFINITY;
      for (size_t j = i + 1; j < poses.size(); ++j) {
        const double d = std::abs(dist[j] - dist[i] - o.delta);
        if (d < best) {
          second = best;
          best = d;
        } else if (d < second) {
          second = d;
        }
      }
      margin = std::min(margin, std::abs(best - tol));
      if (best <= tol) margin = std::min(margin, second - best);
    }
  } else {
    const double to_rad = o.unit == DeltaUnit::degrees ? std::numbers::pi / 180.0 : 1.0;
    auto angle = [&](size_t i, size_t j) {
      return pllvo::geometry::rotation_angle(poses[i].linear().transpose() * poses[j].linear());
    };
    if (!o.all_pairs) {
      double acc = 0.0;
      for (size_t k = 1; k < poses.size(); ++k) {
        acc += angle(k - 1, k) / to_rad;
        margin = std::min(margin, std::abs(acc - o.delta) * to_rad);
        if (acc >= o.delta) acc = 0.0;
      }
    } else {
      for (size_t i = 0; i + 1 < poses.size(); ++i)
        for (size_t j = i + 1; j < poses.size(); ++j) {
          const double a = angle(i, j);
          margin = std::min({margin, std::abs(a - (o.delta - tol) * to_rad), std::abs(a - (o.delta + tol) * to_rad)});
        }
    }
  }
  return margin;
}

void expect_matrix(const Eigen::MatrixXd& got, const json& exp, const std::string& what) {
  ASSERT_EQ(exp.size(), static_cast<size_t>(got.rows())) << what;
  for (Eigen::Index r = 0; r < got.rows(); ++r) {
    ASSERT_EQ(exp[r].size(), static_cast<size_t>(got.cols())) << what;
    for (Eigen::Index k = 0; k < got.cols(); ++k)
      EXPECT_CLOSE(got(r, k), exp[r][k].get<double>(), what + "[" + std::to_string(r) + "][" + std::to_string(k) + "]");
  }
}

void expect_stats(const Statistics& s, const json& e) {
  EXPECT_CLOSE(s.rmse, e.at("rmse").get<double>(), "rmse");
  EXPECT_CLOSE(s.mean, e.at("mean").get<double>(), "mean");
  EXPECT_CLOSE(s.median, e.at("median").get<double>(), "median");
  EXPECT_CLOSE(s.std, e.at("std").get<double>(), "std");
  EXPECT_CLOSE(s.min, e.at("min").get<double>(), "min");
  EXPECT_CLOSE(s.max, e.at("max").get<double>(), "max");
  EXPECT_CLOSE(s.sse, e.at("sse").get<double>(), "sse");
}

/// evo names the trajectories "first/second trajectory"; pllvo says which is which.
std::string evo_wording(std::string message) {
  const std::string ours = "between reference and estimate", evo = "between first trajectory and second trajectory";
  if (const auto pos = message.find(ours); pos != std::string::npos) message.replace(pos, ours.size(), evo);
  return message;
}

class EvoVector : public testing::TestWithParam<std::string> {};

TEST_P(EvoVector, MatchesEvo) {
  ASSERT_NE(GetParam(), kFixtureMissing) << "cannot read expected.json: " << (vector_dir() / "expected.json");
  const json& c = case_by_id(GetParam());
  SCOPED_TRACE(c.at("command").get<std::string>());
  const auto input = load_trajectories(vector_dir() / c.at("est_file").get<std::string>(),
                                       vector_dir() / c.at("ref_file").get<std::string>(),
                                       parse_trajectory_format(c.at("format").get<std::string>()));
  const EvalOptions options = options_of(c);
  const Evaluator evaluator(options);
  const PoseRelation relation = parse_pose_relation(c.at("options").at("pose_relation").get<std::string>());
  const bool is_ape = c.at("tool") == "ape";

  PreparedTrajectories prepared;
  MetricResult result;
  try {
    prepared = evaluator.prepare(input.ref, input.est);
    result = is_ape ? evaluator.ape(prepared, relation) : evaluator.rpe(prepared, relation);
  } catch (const EvalError& e) {
    ASSERT_TRUE(c.contains("expect_error")) << "unexpected " << e.evo_name() << ": " << e.what();
    EXPECT_EQ(e.evo_name(), c.at("expect_error").at("type").get<std::string>());
    EXPECT_EQ(evo_wording(e.what()), c.at("expect_error").at("message").get<std::string>());
    return;
  }
  ASSERT_FALSE(c.contains("expect_error")) << "evo raised " << c.at("expect_error").dump();

  EXPECT_EQ(prepared.num_ref_loaded, c.at("num_poses_ref_loaded").get<size_t>());
  EXPECT_EQ(prepared.num_est_loaded, c.at("num_poses_est_loaded").get<size_t>());

  ASSERT_EQ(prepared.association.has_value(), c.contains("association"));
  if (prepared.association) {
    const json& a = c.at("association");
    const auto [ref_ids, est_ids] = expected_indices(a);
    EXPECT_EQ(prepared.association->size(), a.at("num_matches").get<size_t>());
    EXPECT_EQ(prepared.association->est_longer_than_ref, a.at("est_longer_than_ref").get<bool>());
    EXPECT_EQ(prepared.association->ref_indices, ref_ids);
    EXPECT_EQ(prepared.association->est_indices, est_ids);
    const std::set<size_t> unique(est_ids.begin(), est_ids.end());
    EXPECT_EQ(unique.size() == est_ids.size(), a.at("est_indices_unique").get<bool>());
    EXPECT_CLOSE(decision_margin(input.ref, input.est, options.association),
                 a.at("min_decision_margin_s").get<double>(), "min_decision_margin_s");
  }

  ASSERT_EQ(prepared.alignment.has_value(), c.contains("alignment"));
  if (prepared.alignment) {
    const json& a = c.at("alignment");
    EXPECT_EQ(align_mode_name(prepared.alignment->applied), a.at("applied").get<std::string>());
    expect_matrix(prepared.alignment->transform.rotation, a.at("rotation"), "alignment rotation");
    expect_matrix(prepared.alignment->transform.translation.transpose(), json::array({a.at("translation")}),
                  "alignment translation");
    EXPECT_CLOSE(prepared.alignment->transform.scale, a.at("scale").get<double>(), "alignment scale");
    EXPECT_EQ(prepared.alignment->n_used, a.at("n_used").get<size_t>());
  }
  ASSERT_EQ(prepared.origin_alignment.has_value(), c.contains("origin_alignment"));
  if (prepared.origin_alignment) expect_matrix(prepared.origin_alignment->matrix(), c.at("origin_alignment"), "origin");

  if (!is_ape) {
    EXPECT_EQ(result.pairs.size(), c.at("num_pairs").get<size_t>());
    if (c.contains("pairs")) {
      std::vector<std::pair<size_t, size_t>> pairs;
      for (const auto& p : c.at("pairs")) pairs.emplace_back(p[0].get<size_t>(), p[1].get<size_t>());
      EXPECT_EQ(result.pairs, pairs);
    }
    const PoseList& selected_on = options.pairs_from_reference ? prepared.ref : prepared.est;
    if (c.contains("pair_decision_margin_m"))
      EXPECT_CLOSE(pair_margin(selected_on, options.rpe), c.at("pair_decision_margin_m").get<double>(), "pair margin");
    if (c.contains("pair_decision_margin_rad"))
      EXPECT_CLOSE(pair_margin(selected_on, options.rpe), c.at("pair_decision_margin_rad").get<double>(),
                   "pair margin");
  }
  EXPECT_EQ(unit_name(relation), c.at("unit").get<std::string>());
  ASSERT_EQ(result.errors.size(), c.at("num_errors").get<size_t>());
  expect_stats(result.stats, c.at("stats"));
  if (c.contains("error_array")) {
    const auto& e = c.at("error_array");
    ASSERT_EQ(e.size(), result.errors.size());
    for (size_t i = 0; i < e.size(); ++i) EXPECT_CLOSE(result.errors[i], e[i].get<double>(), "error[" + std::to_string(i) + "]");
  }
}

INSTANTIATE_TEST_SUITE_P(Expected, EvoVector, testing::ValuesIn(case_ids()), test_name);

// The parameterised suite must cover the whole file: 253 cases, ids unique and test-name safe.
TEST(EvoVectors, CoverAllCases) {
  const json& cases = all_cases();
  EXPECT_EQ(cases.size(), 253u);
  std::set<std::string> names;
  size_t errors = 0, arrays = 0;
  for (const auto& c : cases) {
    names.insert(test_name({c.at("id").get<std::string>(), 0}));
    errors += c.contains("expect_error");
    arrays += c.contains("error_array");
  }
  EXPECT_EQ(names.size(), cases.size());
  EXPECT_EQ(errors, 15u);
  EXPECT_EQ(arrays, 63u);
}

}  // namespace
