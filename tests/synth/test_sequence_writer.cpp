// Whole sequences on disk: the EuRoC layout with the synthetic extras, consistent with
// what the generator renders, byte-identical when written twice, and the CLI around it.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <sstream>

#include <opencv2/imgcodecs.hpp>

#include "pllvo/common/error.h"
#include "pllvo/synth/generator.h"
#include "pllvo/synth/sequence_writer.h"

namespace fs = std::filesystem;
using namespace pllvo::synth;

namespace {

fs::path fresh_dir(const std::string& name) {
  const fs::path p = fs::temp_directory_path() / ("pllvo_synth_seq_" + name);
  fs::remove_all(p);
  return p;
}

std::vector<std::string> lines_of(const fs::path& file) {
  std::ifstream f(file);
  std::vector<std::string> out;
  std::string line;
  while (std::getline(f, line)) out.push_back(line);
  return out;
}

std::string bytes_of(const fs::path& file) {
  std::ifstream f(file, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

SequenceSpec short_spec() {
  SequenceSpec spec = preset("medium_lightoff");
  spec.duration_s = 0.3;  // 7 frames
  spec.camera.stereo = true;
  spec.output.lines = true;
  spec.output.depth = true;
  return spec;
}

int run_cli(const std::string& args, std::string* output = nullptr) {
  const std::string cmd = std::string(PLLVO_CLI_PATH) + " " + args + " 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  std::string out;
  char buf[4096];
  while (size_t n = fread(buf, 1, sizeof buf, p)) out.append(buf, n);
  const int status = pclose(p);
  if (output) *output = out;
  return WEXITSTATUS(status);
}

}  // namespace

TEST(SynthSequenceWriter, WritesEuRoCLayoutWithTruthConsistentWithTheGenerator) {
  const fs::path out = fresh_dir("layout");
  const SequenceSpec spec = short_spec();
  write_sequence(spec, out);
  const fs::path mav0 = out / "mav0";
  for (const char* cam : {"cam0", "cam1"}) {
    const auto rows = lines_of(mav0 / cam / "data.csv");
    ASSERT_EQ(rows.size(), 1 + spec.num_frames()) << cam;
    EXPECT_EQ(rows[1], "1500000000000000000,1500000000000000000.png");
    EXPECT_EQ(rows[2], "1500000000050000000,1500000000050000000.png");
    EXPECT_EQ(std::distance(fs::directory_iterator(mav0 / cam / "data"), fs::directory_iterator{}),
              static_cast<long>(spec.num_frames()));
    EXPECT_EQ(lines_of(mav0 / cam / "exposure.csv").size(), 1 + spec.num_frames());
    EXPECT_EQ(lines_of(mav0 / cam / "lines" / "1500000000100000000.csv")[0], "#x1,y1,x2,y2,id,kind,t1,t2,contrast");
  }
  // Ground truth at 200 Hz over [0, 0.3] s: 61 rows, 17 columns.
  const auto gt = lines_of(mav0 / "state_groundtruth_estimate0" / "data.csv");
  ASSERT_EQ(gt.size(), 62u);
  EXPECT_EQ(std::count(gt[5].begin(), gt[5].end(), ','), 16);
  // cam1's T_BS is cam0's moved by the baseline.
  const auto yaml1 = lines_of(mav0 / "cam1" / "sensor.yaml");
  EXPECT_NE(std::find(yaml1.begin(), yaml1.end(), "  data: [1.0, 0.0, 0.0, 0.11,"), yaml1.end());

  // Frame 2 on disk equals a fresh render; its lines and depth match too.
  Generator gen(spec);
  RenderOptions opt;
  opt.lines = true;
  opt.depth = true;
  const RenderedFrame f = gen.render(2, opt);
  const std::string stem = std::to_string(f.stamp_ns);
  const cv::Mat img = cv::imread((mav0 / "cam1" / "data" / (stem + ".png")).string(), cv::IMREAD_UNCHANGED);
  EXPECT_EQ(cv::norm(img, f.cameras[1].image, cv::NORM_INF), 0.0);
  const cv::Mat depth = cv::imread((mav0 / "cam0" / "depth" / (stem + ".png")).string(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(depth.type(), CV_16UC1);
  const float z = f.cameras[0].depth.at<float>(200, 300);
  EXPECT_NEAR(depth.at<uint16_t>(200, 300), z * 1000.0, 0.51);
  const auto seg_rows = lines_of(mav0 / "cam0" / "lines" / (stem + ".csv"));
  ASSERT_EQ(seg_rows.size(), 1 + f.cameras[0].segments.size());
  if (!f.cameras[0].segments.empty()) {
    const auto& s = f.cameras[0].segments[0];
    double x1, y1, x2, y2, t1, t2, contrast;
    int id, kind;
    ASSERT_EQ(std::sscanf(seg_rows[1].c_str(), "%lf,%lf,%lf,%lf,%d,%d,%lf,%lf,%lf", &x1, &y1, &x2, &y2, &id, &kind, &t1, &t2,
                          &contrast),
              9);
    EXPECT_NEAR(x1, s.a.x(), 1e-3);
    EXPECT_NEAR(y2, s.b.y(), 1e-3);
    EXPECT_EQ(id, s.id);
  }
  // The 3-D edges file lists every edge once.
  EXPECT_EQ(lines_of(mav0 / "lines3d.csv").size(), 1 + gen.scene().edges.size());
  // The spec is stored and reads back.
  EXPECT_EQ(to_yaml(load_spec(out / "synth.yaml")), to_yaml(spec));
  fs::remove_all(out);
}

TEST(SynthSequenceWriter, WritingTwiceGivesIdenticalFiles) {
  SequenceSpec spec = preset("difficult_flicker");
  spec.duration_s = 0.2;
  spec.output.lines = true;
  const fs::path a = fresh_dir("twice_a"), b = fresh_dir("twice_b");
  write_sequence(spec, a);
  write_sequence(spec, b);
  int files = 0;
  for (const auto& entry : fs::recursive_directory_iterator(a)) {
    if (!entry.is_regular_file()) continue;
    const fs::path other = b / fs::relative(entry.path(), a);
    ASSERT_TRUE(fs::exists(other)) << other;
    EXPECT_EQ(bytes_of(entry.path()), bytes_of(other)) << entry.path();
    ++files;
  }
  EXPECT_GT(files, 10);
  fs::remove_all(a);
  fs::remove_all(b);
}

TEST(SynthSequenceWriter, RefusesToOverwriteAndLeavesNoPartialOutput) {
  const fs::path out = fresh_dir("exists");
  fs::create_directories(out);
  SequenceSpec spec = preset("easy_normal");
  spec.duration_s = 0.1;
  EXPECT_THROW(write_sequence(spec, out), pllvo::InputError);
  EXPECT_TRUE(fs::is_empty(out));
  WriteOptions wo;
  wo.overwrite = true;
  size_t calls = 0;
  wo.progress = [&](const std::string& name, size_t done, size_t total) {
    EXPECT_EQ(name, "easy_normal");
    EXPECT_EQ(total, 3u);
    calls = done;
  };
  write_sequence(spec, out, wo);
  EXPECT_EQ(calls, 3u);
  EXPECT_TRUE(fs::exists(out / "mav0" / "cam0" / "data.csv"));
  EXPECT_FALSE(fs::exists(out.string() + ".partial"));
  fs::remove_all(out);
}

TEST(SynthCli, RendersAPresetAndExplainsErrors) {
  const fs::path out = fresh_dir("cli");
  std::string text;
  ASSERT_EQ(run_cli("synth --preset easy_lowlight --duration 0.1 --seed 3 --lines --out " + out.string(), &text), 0)
      << text;
  EXPECT_TRUE(fs::exists(out / "mav0" / "cam0" / "lines"));
  EXPECT_EQ(load_spec(out / "synth.yaml").seed, 3u);
  EXPECT_EQ(run_cli("synth --preset easy_lowlight --duration 0.1 --out " + out.string(), &text), 2);
  EXPECT_NE(text.find("already exists"), std::string::npos) << text;
  EXPECT_EQ(run_cli("synth --preset medium_disco --out " + out.string() + "_x", &text), 2);
  EXPECT_NE(text.find("unknown preset 'medium_disco'"), std::string::npos) << text;
  ASSERT_EQ(run_cli("synth --help", &text), 0);
  for (const auto& name : suite_presets()) EXPECT_NE(text.find(name), std::string::npos) << name;
  fs::remove_all(out);
}

TEST(SynthCli, SuiteWritesEveryStandardSequence) {
  const fs::path out = fresh_dir("suite");
  std::string text;
  ASSERT_EQ(run_cli("synth --suite --duration 0.05 --out " + out.string(), &text), 0) << text;
  int sequences = 0;
  for (const auto& name : suite_presets()) {
    EXPECT_TRUE(fs::exists(out / name / "mav0" / "cam0" / "data.csv")) << name;
    EXPECT_EQ(load_spec(out / name / "synth.yaml").name, name);
    ++sequences;
  }
  EXPECT_GE(sequences, 6);
  fs::remove_all(out);
}
