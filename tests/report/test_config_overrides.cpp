// Generic key=value overrides of the VO config, and the bench's method table.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "pllvo/common/error.h"
#include "pllvo/report/bench_methods.h"
#include "pllvo/report/config_overrides.h"

namespace pllvo::report {
namespace {

namespace fs = std::filesystem;

fs::path write_temp(const std::string& name, const std::string& text) {
  const fs::path p = fs::temp_directory_path() / ("pllvo_report_" + name);
  std::ofstream(p) << text;
  return p;
}

TEST(ConfigOverride, ParsesKeyAndTypedValue) {
  const auto o = parse_override("keyframes.max_interval_s=0.5");
  EXPECT_EQ(o.key, "keyframes.max_interval_s");
  EXPECT_DOUBLE_EQ(o.value.as<double>(), 0.5);
  EXPECT_FALSE(parse_override("pose.use_lines=false").value.as<bool>());
  EXPECT_EQ(parse_override("frontend.type=orb").value.as<std::string>(), "orb");
  EXPECT_THROW(parse_override("frontend.type"), InputError);
  EXPECT_THROW(parse_override("=3"), InputError);
}

TEST(ConfigOverride, AppliesNestedKeysOverABaseDocument) {
  const YAML::Node base = YAML::Load("frontend: {max_points: 123}\nklt: {levels: 2}");
  const auto c = make_vo_config(base,
                                {parse_override("frontend.type=shitomasi"), parse_override("klt.levels=4"),
                                 parse_override("lines.cross_constraint.enabled=false"),
                                 parse_override("keyframes.use_line_trigger=false")},
                                "test");
  EXPECT_EQ(c.frontend.type, "shitomasi");
  EXPECT_EQ(c.frontend.max_points, 123);  // the base survives where no override touches it
  EXPECT_EQ(c.klt.levels, 4);             // the override wins over the base
  EXPECT_FALSE(c.lines.cross_constraint.enabled);
  EXPECT_FALSE(c.keyframes.use_line_trigger);
  EXPECT_TRUE(c.keyframes.use_point_trigger);  // defaults elsewhere
  EXPECT_EQ(base["klt"]["levels"].as<int>(), 2);  // the base document itself is not modified
}

TEST(ConfigOverride, UnknownKeyOrBadValueNamesTheKeyAndSource) {
  try {
    make_vo_config({}, {parse_override("frontend.typo=1")}, "bench.yaml (method x)");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("frontend.typo"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("method x"), std::string::npos) << e.what();
  }
  EXPECT_THROW(make_vo_config({}, {parse_override("frontend.type=sift")}, "s"), InputError);
  EXPECT_THROW(make_vo_config({}, {parse_override("frontend.max_points=many")}, "s"), InputError);
  // A value where a section is expected.
  EXPECT_THROW(make_vo_config({}, {parse_override("frontend=3"), parse_override("frontend.type=orb")}, "s"),
               InputError);
}

TEST(ConfigOverride, FlattensNestedAndDottedMappingsAlike) {
  const auto a = flatten_overrides(YAML::Load("{frontend: {type: orb}, klt.levels: 3}"));
  ASSERT_EQ(a.size(), 2u);
  EXPECT_EQ(a[0].key, "frontend.type");
  EXPECT_EQ(a[1].key, "klt.levels");
}

TEST(BenchMethods, ShippedTableHasEveryBaselineAndAblationAndEachBuildsAValidConfig) {
  const fs::path file = fs::path(PLLVO_SOURCE_DIR) / "config/bench.yaml";
  const auto table = load_bench_methods(file);
  const std::vector<std::string> expected = {"orb",       "klt",           "sp-mnn",
                                             "pllvo",     "pllvo-no-lines", "pllvo-mnn",
                                             "pllvo-no-line-flow", "pllvo-no-cross", "pllvo-no-overlap-trigger",
                                             "pllvo-lg-full"};
  const auto selected = table.select({}, file);
  ASSERT_EQ(selected.size(), expected.size());
  for (size_t i = 0; i < expected.size(); ++i) EXPECT_EQ(selected[i].name, expected[i]);
  EXPECT_EQ(table.speed_baseline, "orb");
  std::map<std::string, vo::VoConfig> configs;
  for (const auto& m : selected) {
    auto all = table.common;
    all.insert(all.end(), m.overrides.begin(), m.overrides.end());
    configs[m.name] = make_vo_config({}, all, file.string() + " (method " + m.name + ")");
  }
  EXPECT_EQ(configs["orb"].frontend.type, "orb");
  EXPECT_EQ(configs["klt"].frontend.type, "shitomasi");
  EXPECT_EQ(configs["sp-mnn"].frontend.type, "superpoint");
  EXPECT_EQ(configs["sp-mnn"].mapping.matcher, "mnn");
  EXPECT_EQ(configs["pllvo-mnn"].mapping.matcher, "mnn");
  EXPECT_FALSE(configs["pllvo-no-cross"].lines.cross_constraint.enabled);
  EXPECT_TRUE(configs["pllvo"].lines.cross_constraint.enabled);
  EXPECT_FALSE(configs["pllvo-no-overlap-trigger"].keyframes.use_line_trigger);
  EXPECT_TRUE(configs["pllvo"].keyframes.use_line_trigger);
  EXPECT_EQ(configs["pllvo-lg-full"].mapping.matcher, "lightglue");
  EXPECT_LE(configs["pllvo-lg-full"].mapping.lightglue_depth_confidence, 0.0);
  EXPECT_LE(configs["pllvo-lg-full"].mapping.lightglue_width_confidence, 0.0);
  EXPECT_GT(configs["pllvo"].mapping.lightglue_depth_confidence, 0.0);
}

TEST(BenchMethods, BadTablesAreInputErrors) {
  EXPECT_THROW(load_bench_methods("/nonexistent/bench.yaml"), InputError);
  EXPECT_THROW(load_bench_methods(write_temp("dup.yaml", "methods:\n  - {name: a}\n  - {name: a}\nspeed_baseline: a\n")),
               InputError);
  EXPECT_THROW(load_bench_methods(write_temp("nobase.yaml", "methods:\n  - {name: a}\n")), InputError);  // no orb
  EXPECT_THROW(load_bench_methods(write_temp("typo.yaml", "methods:\n  - {name: orb, sett: {}}\n")), InputError);
  const auto f = write_temp("ok.yaml", "methods:\n  - {name: orb, set: {frontend.type: orb}}\n");
  const auto t = load_bench_methods(f);
  try {
    t.select({"orb", "nope"}, f);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("nope"), std::string::npos);
  }
}

}  // namespace
}  // namespace pllvo::report
