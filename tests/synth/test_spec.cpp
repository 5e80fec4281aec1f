// Sequence specs: presets, the default YAML, YAML round trip and clear errors.
#include <gtest/gtest.h>

#include <fstream>
#include <set>

#include "pllvo/common/error.h"
#include "pllvo/synth/spec.h"

namespace fs = std::filesystem;
using namespace pllvo::synth;

namespace {
fs::path write_temp(const std::string& name, const std::string& text) {
  const auto p = fs::temp_directory_path() / ("pllvo_synth_" + name);
  std::ofstream(p) << text;
  return p;
}
}  // namespace

TEST(SynthSpec, DefaultConfigFileListsExactlyTheDefaults) {
  const SequenceSpec loaded = load_spec(fs::path(PLLVO_SOURCE_DIR) / "config" / "synth.yaml");
  SequenceSpec defaults;
  EXPECT_EQ(to_yaml(loaded), to_yaml(defaults));
}

TEST(SynthSpec, YamlRoundTripKeepsEveryField) {
  SequenceSpec s = preset("difficult_flicker");
  s.seed = 42;
  s.camera.stereo = true;
  s.camera.T_body_cam0.translation() = Eigen::Vector3d(0.1, -0.2, 0.3);
  s.camera.T_body_cam0.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  s.output.lines = true;
  const auto file = write_temp("roundtrip.yaml", to_yaml(s));
  const SequenceSpec back = load_spec(file);
  EXPECT_EQ(to_yaml(back), to_yaml(s));
  EXPECT_TRUE(back.camera.T_body_cam0.isApprox(s.camera.T_body_cam0, 1e-15));
}

TEST(SynthSpec, PresetInFileThenOverrides) {
  const auto file = write_temp("preset.yaml", "preset: easy_lowlight\nseed: 9\nlighting:\n  low_light_level: 0.02\n");
  const SequenceSpec s = load_spec(file);
  EXPECT_EQ(s.name, "easy_lowlight");
  EXPECT_EQ(s.seed, 9u);
  EXPECT_EQ(s.lighting.mode, "low_light");
  EXPECT_DOUBLE_EQ(s.lighting.low_light_level, 0.02);
  EXPECT_DOUBLE_EQ(s.motion.mean_speed, motion_level("easy").mean_speed);
}

TEST(SynthSpec, ErrorsNameTheKey) {
  const auto expect_key = [](const std::string& text, const std::string& key) {
    try {
      load_spec(write_temp("bad.yaml", text));
      ADD_FAILURE() << "no error for " << text;
    } catch (const pllvo::InputError& e) {
      EXPECT_EQ(e.key(), key) << e.what();
    }
  };
  expect_key("camera:\n  widht: 10\n", "camera.widht");
  expect_key("lighting:\n  mode: disco\n", "lighting.mode");
  expect_key("duration_s: -1\n", "duration_s");
  expect_key("sensor:\n  max_gain: abc\n", "sensor.max_gain");
  expect_key("camera:\n  distortion: [1, 2, 3]\n", "camera.distortion");
  expect_key("sensor:\n  supersample: 0\n", "sensor.supersample");
  expect_key("sensor:\n  supersample: 5\n", "sensor.supersample");
  expect_key("preset: nonsense\n", "preset");
  expect_key("camera:\n  T_body_cam0: [2, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]\n", "camera.T_body_cam0");
}

TEST(SynthSpec, SuiteCoversMotionTimesLightingPlusLowTexture) {
  const auto suite = suite_presets();
  EXPECT_GE(suite.size(), 6u);
  const std::set<std::string> names(suite.begin(), suite.end());
  for (const char* level : {"easy", "medium", "difficult"})
    for (const char* light : {"normal", "lowlight", "flicker"})
      EXPECT_TRUE(names.count(std::string(level) + "_" + light)) << level << "_" << light;
  bool low_texture = false;
  for (const auto& n : suite) low_texture = low_texture || preset(n).scene.texture == "low";
  EXPECT_TRUE(low_texture);
  for (const auto& p : presets()) {
    const SequenceSpec s = preset(p.name);
    EXPECT_NO_THROW(validate(s)) << p.name;
    EXPECT_GE(s.duration_s, 20);
    EXPECT_LE(s.duration_s, 60);
  }
  EXPECT_THROW(preset("medium_disco"), pllvo::InputError);
  EXPECT_EQ(preset("difficult_lowlight").lighting.mode, "low_light");
  EXPECT_EQ(preset("easy_flicker").lighting.mode, "flicker");
}
