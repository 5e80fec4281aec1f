#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>

#include "pllvo/common/fixtures.h"
#include "pllvo/eval/eval_report.h"

namespace fs = std::filesystem;
using namespace pllvo::eval;

TEST(EvalReport, JsonCarriesTheRunAndIsWrittenWhole) {
  const auto v = pllvo::shared_path("testvectors/eval");
  EvalRequest req;
  req.est_file = v / "est_e4_kitti.txt";
  req.ref_file = v / "ref_kitti.txt";
  req.options.align = AlignMode::sim3;
  const auto report = run_evaluation(req);  // auto-detected KITTI: paired by index
  EXPECT_FALSE(report.prepared.association.has_value());
  ASSERT_EQ(report.results.size(), 4u);  // APE, RPE x trans_part, angle_deg
  const auto j = report_to_json(report);
  EXPECT_TRUE(j.at("association").is_null());
  EXPECT_EQ(j.at("num_compared_poses"), 600);
  EXPECT_EQ(j.at("results")[2].at("metric"), "rpe");
  EXPECT_EQ(j.at("results")[2].at("num_pairs"), 599);
  EXPECT_DOUBLE_EQ(j.at("alignment").at("scale").get<double>(), report.prepared.alignment->transform.scale);

  const fs::path file = fs::temp_directory_path() / ("pllvo_eval_report_" + std::to_string(::getpid()) + ".json");
  write_json_file(j, file);
  std::ifstream in(file);
  EXPECT_EQ(nlohmann::json::parse(in), j);
  fs::remove(file);
  EXPECT_THROW(write_json_file(j, fs::temp_directory_path() / "pllvo_no_such_dir" / "x.json"), pllvo::InputError);

  const auto table = format_report(report);
  EXPECT_NE(table.find("matched    600 poses (paired by index: no timestamps)"), std::string::npos) << table;
  EXPECT_NE(table.find("(Sim3)"), std::string::npos) << table;
}

TEST(EvalReport, OptionsLoadFromYamlAndRejectTypos) {
  const fs::path dir = fs::temp_directory_path() / ("pllvo_eval_yaml_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "ok.yaml") << "t_offset: 0.02\nalign: sim3\ndelta: 2.0\ndelta_unit: m\nall_pairs: true\n";
  std::ofstream(dir / "typo.yaml") << "t_ofset: 0.02\n";
  EvalOptions o;
  o.load(pllvo::ConfigNode::load_file(dir / "ok.yaml"));
  EXPECT_EQ(o.association.t_offset, 0.02);
  EXPECT_EQ(o.align, AlignMode::sim3);
  EXPECT_EQ(o.rpe.unit, DeltaUnit::meters);
  EXPECT_TRUE(o.rpe.all_pairs);
  EXPECT_EQ(o.min_poses, 3u);
  EvalOptions p;
  EXPECT_THROW(p.load(pllvo::ConfigNode::load_file(dir / "typo.yaml")), pllvo::InputError);
  // The shipped defaults file holds exactly the defaults in code.
  EvalOptions shipped;
  shipped.load(pllvo::ConfigNode::load_file(fs::path(PLLVO_SOURCE_DIR) / "config/eval.yaml"));
  EXPECT_EQ(shipped.association.t_max_diff, EvalOptions{}.association.t_max_diff);
  EXPECT_EQ(shipped.rpe.delta_tol, EvalOptions{}.rpe.delta_tol);
  fs::remove_all(dir);
}
