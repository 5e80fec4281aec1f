#include <gtest/gtest.h>

#include <fstream>

#include "pllvo/common/fixtures.h"
#include "pllvo/common/yaml_config.h"

namespace fs = std::filesystem;

namespace {
fs::path write_temp(const std::string& name, const std::string& text) {
  const auto p = fs::temp_directory_path() / ("pllvo_test_" + name);
  std::ofstream(p) << text;
  return p;
}
}  // namespace

TEST(ConfigNode, OverridesDefaultsAndRejectsUnknownKeys) {
  const auto file = write_temp("cfg.yaml", "a: 3\nsub:\n  b: 2.5\n");
  const auto cfg = pllvo::ConfigNode::load_file(file);
  int a = 1;
  double b = 0, c = 7;
  cfg.get("a", a);
  const auto sub = cfg.child("sub");
  sub.get("b", b);
  sub.get("c", c);
  EXPECT_EQ(a, 3);
  EXPECT_EQ(b, 2.5);
  EXPECT_EQ(c, 7);  // default kept
  EXPECT_NO_THROW(cfg.reject_unknown_keys());

  const auto bad = pllvo::ConfigNode::load_file(write_temp("cfg2.yaml", "a: 3\ntypo: 1\n"));
  bad.get("a", a);
  try {
    bad.reject_unknown_keys();
    FAIL();
  } catch (const pllvo::InputError& e) {
    EXPECT_EQ(e.key(), "typo");
  }
}

TEST(ConfigNode, MalformedYamlNamesTheLine) {
  const auto file = write_temp("bad.yaml", "a: 1\nb: [1, 2\nc: 3\n");
  try {
    pllvo::ConfigNode::load_file(file);
    FAIL();
  } catch (const pllvo::InputError& e) {
    EXPECT_EQ(e.file(), file.string());
    EXPECT_GE(e.line(), 2);
  }
}

TEST(ConfigNode, WrongTypeNamesTheKey) {
  const auto cfg = pllvo::ConfigNode::load_file(write_temp("type.yaml", "sub:\n  n: hello\n"));
  int n = 0;
  try {
    cfg.child("sub").get("n", n);
    FAIL();
  } catch (const pllvo::InputError& e) {
    EXPECT_EQ(e.key(), "sub.n");
  }
  EXPECT_THROW(pllvo::ConfigNode::load_file("/nonexistent/x.yaml"), pllvo::InputError);
}

TEST(ConfigNode, RecordingListsEveryKeyAskedForWithItsDefault) {
  const auto node = pllvo::ConfigNode::recording();
  int count = 3;
  double scale = 0.7;
  float threshold = 0.0005f;
  bool on = true;
  std::string name;
  std::vector<double> weights = {1.0, 0.5};
  node.get("count", count);
  node.child("sub").get("scale", scale);
  node.child("sub").child("deep").get("on", on);
  node.get("threshold", threshold);
  node.get("name", name);
  node.get("weights", weights);
  node.record_default("choice", "huber");
  const auto r = node.recorded();
  ASSERT_EQ(r.size(), 7u);
  EXPECT_EQ(r[0].key, "count");
  EXPECT_EQ(r[0].value, "3");
  EXPECT_EQ(r[1].key, "sub.scale");
  EXPECT_EQ(r[1].value, "0.7");
  EXPECT_EQ(r[2].key, "sub.deep.on");
  EXPECT_EQ(r[2].value, "true");
  EXPECT_EQ(r[3].value, "0.0005");  // a float's own digits, not 0.000500000023748726
  EXPECT_EQ(r[4].value, "\"\"");
  EXPECT_EQ(r[5].value, "[1, 0.5]");
  EXPECT_EQ(r[6].key, "choice");
  // A node read from a file records nothing.
  const auto file = write_temp("rec.yaml", "count: 4\n");
  const auto loaded = pllvo::ConfigNode::load_file(file);
  loaded.get("count", count);
  loaded.get("other", scale);
  EXPECT_TRUE(loaded.recorded().empty());
}

TEST(Fixtures, SharedDirIsPresent) {
  // The whole suite relies on the shared fixtures; this fails loudly when they are missing.
  EXPECT_TRUE(fs::is_directory(pllvo::shared_path("data")));
  EXPECT_TRUE(fs::is_directory(pllvo::shared_path("testvectors")));
  EXPECT_THROW(pllvo::shared_path("no_such_fixture"), pllvo::InputError);
}
