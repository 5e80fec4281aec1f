// The ablation / baseline switches of VoConfig (what `pllvo bench` varies) each change what
// the pipeline does, seen in stats.json, on one short rendered stereo sequence
// (easy_normal, 2 s), deterministic single-thread mode.
#include <unistd.h>

#include <filesystem>

#include <gtest/gtest.h>

#include "pllvo/common/error.h"
#include "pllvo/common/fixtures.h"
#include "pllvo/io/sequence.h"
#include "pllvo/nn/model_files.h"
#include "pllvo/synth/sequence_writer.h"
#include "pllvo/synth/spec.h"
#include "pllvo/vo/run_sequence.h"
#include "synthetic_sequence.h"

namespace pllvo::vo {
namespace {
namespace fs = std::filesystem;

class PipelineSwitches : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    // One folder per process: CTest runs each test of this suite in its own process, in parallel.
    dir_ = new fs::path(fs::temp_directory_path() / ("pllvo_vo_switches_easy_normal_" + std::to_string(::getpid())));
    fs::remove_all(*dir_);
    synth::SequenceSpec spec = synth::preset("easy_normal");
    spec.duration_s = 2;
    spec.camera.stereo = true;
    synth::write_sequence(spec, *dir_);
    sequence_ = io::open_sequence(*dir_).release();
  }
  static void TearDownTestSuite() {
    delete baseline_;
    baseline_ = nullptr;
    delete sequence_;
    fs::remove_all(*dir_);
    delete dir_;
  }

  static VoConfig base() { return testing::deterministic(); }
  static nlohmann::json run(const VoConfig& c) {
    c.validate();
    const RunSummary s = run_sequence(*sequence_, c, RunOptions{});
    EXPECT_EQ(s.tracked_frames, s.frames);
    return s.stats;
  }
  /// The default pipeline's run, shared by the tests (the sequence and mode are fixed).
  static const nlohmann::json& baseline() {
    if (!baseline_) baseline_ = new nlohmann::json(run(base()));
    return *baseline_;
  }
  static double per_frame_mean(const nlohmann::json& j, const std::string& name) {
    return j["per_frame"].contains(name) ? j["per_frame"][name]["mean"].get<double>() : 0.0;
  }
  static long long count(const nlohmann::json& j, const std::string& name) { return testing::stats_count(j, name); }

  static fs::path* dir_;
  static io::Sequence* sequence_;
  static nlohmann::json* baseline_;
};
nlohmann::json* PipelineSwitches::baseline_ = nullptr;
fs::path* PipelineSwitches::dir_ = nullptr;
io::Sequence* PipelineSwitches::sequence_ = nullptr;

TEST_F(PipelineSwitches, LinesOffRemovesLinesEverywhere) {
  const auto& on = baseline();
  EXPECT_GT(on["map"]["lines"].get<int>(), 0);
  EXPECT_GT(per_frame_mean(on, "tracked_lines"), 0.0);
  EXPECT_TRUE(on["timing_ms"].contains("line_tracking"));

  VoConfig c = base();
  c.pipeline.lines = false;
  const auto off = run(c);
  EXPECT_EQ(off["map"]["lines"].get<int>(), 0);
  EXPECT_EQ(per_frame_mean(off, "tracked_lines"), 0.0);
  EXPECT_FALSE(off["timing_ms"].contains("line_tracking"));
  EXPECT_FALSE(off["timing_ms"].contains("kf_lines"));
  EXPECT_FALSE(off["pipeline"]["lines"].get<bool>());
}

TEST_F(PipelineSwitches, LineRedetectionReplacesLineFlow) {
  const auto& flow = baseline();
  EXPECT_EQ(count(flow, "line_redetections"), 0);
  VoConfig c = base();
  c.pipeline.line_tracking = "redetect";
  const auto redetect = run(c);
  // Every tracked frame with lines to follow detects lines itself...
  EXPECT_GT(count(redetect, "line_redetections"), 25);
  // ...and still follows lines with it (map lines measured in the pose).
  EXPECT_GT(redetect["map"]["lines"].get<int>(), 0);
  EXPECT_GT(per_frame_mean(redetect, "tracked_lines"), 0.0);
  EXPECT_EQ(redetect["pipeline"]["line_tracking"].get<std::string>(), "redetect");
}

TEST_F(PipelineSwitches, CrossConstraintSwitch) {
  // With its default thresholds the constraint removes nothing on these clean rendered
  // frames (no bundles of > 2 shallow overlaps: measured, same line counts on and off); a
  // strict setting (any shallow overlap counts) shows that the switch gates it.
  VoConfig c = base();
  c.lines.cross_constraint.max_shallow_overlaps = 0;
  c.lines.cross_constraint.max_overlap_angle_deg = 30;
  const auto on = run(c);
  c.lines.cross_constraint.enabled = false;
  const auto off = run(c);
  EXPECT_GT(per_frame_mean(off, "kf_lines"), per_frame_mean(on, "kf_lines"));
  EXPECT_FALSE(off["pipeline"]["cross_constraint"].get<bool>());
}

TEST_F(PipelineSwitches, LineKeyframeTrigger) {
  VoConfig c = base();
  c.keyframes.line_angle_distance_deg = 1.0;  // fires readily on this sequence
  const auto on = run(c);
  EXPECT_GT(on["keyframes_by_reason"]["line_angles"].get<int>(), 0);
  c.keyframes.use_line_trigger = false;
  const auto off = run(c);
  EXPECT_EQ(off["keyframes_by_reason"]["line_angles"].get<int>(), 0);
}

TEST_F(PipelineSwitches, MatcherChoiceForBinaryDescriptors) {
  VoConfig c = base();
  const auto& ratio = baseline();
  EXPECT_EQ(ratio["matcher"].get<std::string>(), "hamming-ratio");
  c.mapping.matcher = "mnn";
  const auto mnn = run(c);
  EXPECT_EQ(mnn["matcher"].get<std::string>(), "hamming-mnn");
  // Mutual nearest neighbours without the ratio test keep more (also ambiguous) matches.
  EXPECT_GT(per_frame_mean(mnn, "kf_matches"), per_frame_mean(ratio, "kf_matches"));
  c.mapping.matcher = "lightglue";
  EXPECT_THROW(run(c), InputError);  // LightGlue needs SuperPoint descriptors
}

TEST_F(PipelineSwitches, FrontEnds) {
  VoConfig c = base();
  c.frontend.type = "shitomasi";
  const auto st = run(c);
  EXPECT_EQ(st["frontend"].get<std::string>(), "shitomasi");
  EXPECT_GT(st["keyframes"].get<int>(), 1);

  c = base();
  c.frontend.type = "superpoint";
  c.frontend.superpoint_weights = shared_path("models/superpoint_v1.safetensors").string();
  c.mapping.matcher = "mnn";
  const auto sp = run(c);
  EXPECT_EQ(sp["frontend"].get<std::string>(), "superpoint");
  EXPECT_EQ(sp["matcher"].get<std::string>(), "mnn");
  EXPECT_GT(per_frame_mean(sp, "kf_matches"), 50.0);
  ASSERT_TRUE(sp.contains("trajectory_error"));
  EXPECT_LT(sp["trajectory_error"]["ate_percent_of_path"].get<double>(), 2.0);

  // auto: LightGlue when its weights are found, else MNN; lightglue by name: no fallback.
  c.mapping.matcher = "lightglue";
  if (nn::find_weights({}, nn::lightglue_weight_names()).found)
    EXPECT_EQ(run(c)["matcher"].get<std::string>(), "lightglue");
  else
    EXPECT_THROW(run(c), InputError);
}

}  // namespace
}  // namespace pllvo::vo

namespace pllvo::vo {
namespace {

// The threaded pipeline (not deterministic, so no exact numbers): with the keyframe work on
// one thread or split in two stages (detection beside the previous keyframe's mapping), every
// frame is tracked and the trajectory holds; keyframes are made and their times recorded.
TEST_F(PipelineSwitches, ThreadedRunsWithOneOrTwoKeyframeStagesTrack) {
  for (int stages : {1, 2}) {
    VoConfig c = base();
    c.run.threaded = true;
    c.run.keyframe_stages = stages;
    const auto j = run(c);
    EXPECT_TRUE(j["threaded"].get<bool>());
    EXPECT_GT(j["keyframes"].get<int>(), 2) << "stages " << stages;
    ASSERT_TRUE(j.contains("trajectory_error"));
    EXPECT_LT(j["trajectory_error"]["ate_percent_of_path"].get<double>(), 2.0) << "stages " << stages;
    // The keyframe total counts both parts: detection and the rest.
    EXPECT_GE(j["timing_ms"]["kf_total"]["mean"].get<double>(), j["timing_ms"]["kf_detect"]["mean"].get<double>());
  }
}

}  // namespace
}  // namespace pllvo::vo
