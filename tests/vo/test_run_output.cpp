#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "pllvo/common/error.h"
#include "pllvo/io/trajectory.h"
#include "pllvo/vo/run_output.h"
#include "pllvo/vo/run_stats.h"

namespace pllvo::vo {
namespace fs = std::filesystem;
namespace {

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("pllvo_vo_output_" + name);
  fs::remove_all(dir);
  return dir;
}

std::vector<fs::path> files_in(const fs::path& dir) {
  std::vector<fs::path> out;
  for (const auto& e : fs::directory_iterator(dir)) out.push_back(e.path().filename());
  return out;
}

std::vector<FrameRecord> records_with_gaps() {
  std::vector<FrameRecord> r;
  for (size_t i = 0; i < 10; ++i) {
    FrameRecord f;
    f.index = i;
    f.timestamp = 100.0 + 0.05 * i;
    f.tracked = !(i == 0 || i == 4 || i == 5 || i == 9);
    f.T_world_cam = geometry::make_pose(
        Eigen::AngleAxisd(0.1 * i, Eigen::Vector3d(0.3, 1, 0.2).normalized()).toRotationMatrix(),
        Eigen::Vector3d(0.5 * i, -0.25 * i, 1.0 + i));
    r.push_back(f);
  }
  return r;
}

TEST(RunOutput, TrajectoryHoldsTrackedFramesOnlyAndRoundTrips) {
  const auto records = records_with_gaps();
  const fs::path dir = fresh_dir("traj");
  write_trajectory_tum(tracked_trajectory(records), dir / "trajectory.tum");
  const io::Trajectory back = io::read_tum(dir / "trajectory.tum");
  ASSERT_EQ(back.size(), 6u);
  size_t k = 0;
  for (const auto& r : records) {
    if (!r.tracked) continue;
    EXPECT_DOUBLE_EQ(back.stamps[k], r.timestamp);
    EXPECT_TRUE(back.poses[k].isApprox(r.T_world_cam, 1e-12));
    ++k;
  }
  EXPECT_EQ(files_in(dir).size(), 1u) << "temporary file left behind";
}

// Frames 1-3 follow keyframe 1 and 6-8 keyframe 6 (a new segment from frame 6). The adjustment
// moved both keyframes; each frame keeps its tracked pose relative to its keyframe, the
// segment's frames before its first keyframe keep theirs, and lost frames stay absent.
TEST(RunOutput, AnchoredTrajectoryCarriesEachKeyframesCorrectionToItsFrames) {
  auto records = records_with_gaps();  // tracked: 1, 2, 3, 6, 7, 8
  for (auto& r : records) r.segment = r.index >= 6 ? 1 : 0;
  const geometry::Pose move1 = geometry::make_pose(
      Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitY()).toRotationMatrix(), Eigen::Vector3d(0.2, 0, -0.1));
  const geometry::Pose move6 = geometry::make_pose(Eigen::Matrix3d::Identity(), Eigen::Vector3d(0, 0.3, 0));
  std::vector<KeyframePose> keyframes = {{7, records[7].timestamp, 1, move6 * records[7].T_world_cam},
                                         {1, records[1].timestamp, 0, move1 * records[1].T_world_cam}};
  const io::Trajectory anchored = keyframe_anchored_trajectory(records, keyframes);
  ASSERT_EQ(anchored.size(), 6u);
  const geometry::Pose expected[] = {move1 * records[1].T_world_cam, move1 * records[2].T_world_cam,
                                     move1 * records[3].T_world_cam, records[6].T_world_cam,
                                     move6 * records[7].T_world_cam, move6 * records[8].T_world_cam};
  for (size_t k = 0; k < 6; ++k) {
    EXPECT_TRUE(anchored.poses[k].isApprox(expected[k], 1e-12)) << "pose " << k;
    EXPECT_FALSE(anchored.poses[k].isApprox(tracked_trajectory(records).poses[k], 1e-6) && k != 3) << "pose " << k;
  }
  // A keyframe of the old segment does not carry a later segment's frames.
  keyframes.erase(keyframes.begin());
  const io::Trajectory without = keyframe_anchored_trajectory(records, keyframes);
  EXPECT_TRUE(without.poses[5].isApprox(records[8].T_world_cam, 1e-12));
}

TEST(RunOutput, LostIntervalsAreMaximalRuns) {
  const auto lost = lost_intervals(records_with_gaps());
  ASSERT_EQ(lost.size(), 3u);
  EXPECT_EQ(lost[0].first_frame, 0u);
  EXPECT_EQ(lost[0].last_frame, 0u);
  EXPECT_EQ(lost[1].first_frame, 4u);
  EXPECT_EQ(lost[1].last_frame, 5u);
  EXPECT_DOUBLE_EQ(lost[1].first_time, 100.2);
  EXPECT_DOUBLE_EQ(lost[1].last_time, 100.25);
  EXPECT_EQ(lost[2].first_frame, 9u);
}

TEST(RunOutput, MapPlyListsPointsAndLineSegments) {
  MapData map;
  map.add_point({1, 2, 3});
  map.add_point({4, 5, 6});
  map.add_point({7, 8, 9});
  map.add_line({0, 0, 1}, {1, 0, 1});
  map.add_line({0, 1, 2}, {0, 2, 2});
  const fs::path file = fresh_dir("ply") / "map.ply";
  write_map_ply(map, file);
  std::ifstream in(file);
  std::string line;
  std::vector<std::string> header, body;
  bool in_body = false;
  while (std::getline(in, line)) {
    if (in_body) body.push_back(line);
    else header.push_back(line);
    if (line == "end_header") in_body = true;
  }
  EXPECT_EQ(header.front(), "ply");
  EXPECT_NE(std::find(header.begin(), header.end(), "element vertex 7"), header.end());
  EXPECT_NE(std::find(header.begin(), header.end(), "element edge 2"), header.end());
  ASSERT_EQ(body.size(), 9u);
  EXPECT_EQ(body[0], "1 2 3 200 200 200");
  EXPECT_EQ(body[4], "1 0 1 255 40 40");
  EXPECT_EQ(body[7], "3 4");
  EXPECT_EQ(body[8], "5 6");
}

TEST(RunOutput, FailedWriteKeepsTheOldFileAndLeavesNoTemporary) {
  const fs::path dir = fresh_dir("atomic");
  const fs::path file = dir / "stats.json";
  write_json({{"version", 1}}, file);
  EXPECT_THROW(write_atomically(file,
                                [](std::ostream& out) {
                                  out << "{\"version\": 2, half";
                                  throw InputError("simulated failure while writing");
                                }),
               InputError);
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(nlohmann::json::parse(text.str())["version"], 1);
  EXPECT_EQ(files_in(dir).size(), 1u);
}

TEST(RunStats, TimingSummaryHasMeanMedianAndP95) {
  std::vector<double> v;
  for (int i = 100; i >= 1; --i) v.push_back(i);
  const TimingSummary s = summarize_timing(v);
  EXPECT_EQ(s.count, 100u);
  EXPECT_DOUBLE_EQ(s.mean_ms, 50.5);
  EXPECT_DOUBLE_EQ(s.median_ms, 50.5);
  EXPECT_NEAR(s.p95_ms, 95.05, 1e-9);
  EXPECT_DOUBLE_EQ(s.max_ms, 100);
  EXPECT_DOUBLE_EQ(s.total_ms, 5050);
}

TEST(RunStats, JsonHasTimingCountsAndPerFrameSamples) {
  RunStats stats;
  stats.add_time("klt", 2.0);
  stats.add_time("klt", 4.0);
  stats.add_count("keyframes.few_points", 3);
  stats.add_sample("tracked_points", 100);
  stats.add_sample("tracked_points", 300);
  const auto j = stats.to_json();
  EXPECT_DOUBLE_EQ(j["timing_ms"]["klt"]["mean"].get<double>(), 3.0);
  EXPECT_EQ(j["counts"]["keyframes.few_points"].get<long long>(), 3);
  EXPECT_DOUBLE_EQ(j["per_frame"]["tracked_points"]["mean"].get<double>(), 200.0);
}

}  // namespace
}  // namespace pllvo::vo
