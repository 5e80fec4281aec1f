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

TEST(Fixtures, SharedDirIsPresent) {
  // The whole suite relies on the shared fixtures; this fails loudly when they are missing.
  EXPECT_TRUE(fs::is_directory(pllvo::shared_path("data")));
  EXPECT_TRUE(fs::is_directory(pllvo::shared_path("testvectors")));
  EXPECT_THROW(pllvo::shared_path("no_such_fixture"), pllvo::InputError);
}
