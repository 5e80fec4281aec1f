#pragma once
// Files of `pllvo run --out DIR`: trajectory.tum, keyframes.tum, stats.json, map.ply.
// Every file is written to a temporary name and renamed, so none is ever half-written.
#include <filesystem>
#include <functional>
#include <ostream>
#include <vector>

#include <nlohmann/json.hpp>

#include "pllvo/geometry/pose.h"
#include "pllvo/io/trajectory.h"
#include "pllvo/vo/map.h"

namespace pllvo::vo {

/// Calls `write` on a temporary file beside `path`, then renames it to `path`. The parent
/// folder is created. On failure (stream error or exception) the temporary file is removed
/// and InputError names `path`.
void write_atomically(const std::filesystem::path& path, const std::function<void(std::ostream&)>& write);

/// What the pipeline knows about one input frame once it is processed.
struct FrameRecord {
  size_t index = 0;
  double timestamp = 0;
  bool tracked = false;  ///< a pose was estimated (false: lost, or not initialised yet)
  geometry::Pose T_world_cam = geometry::Pose::Identity();
  int tracked_points = 0;
  int tracked_lines = 0;
  int segment = 0;  ///< map segment: increases with every re-initialisation after a loss
};

/// Maximal runs of consecutive untracked frames.
struct LostInterval {
  size_t first_frame = 0, last_frame = 0;
  double first_time = 0, last_time = 0;
};
std::vector<LostInterval> lost_intervals(const std::vector<FrameRecord>& records);

/// TUM trajectory of the tracked frames only (lost frames are absent), each pose as it was
/// tracked (what a live consumer received).
io::Trajectory tracked_trajectory(const std::vector<FrameRecord>& records);

/// A keyframe's pose at the end of the run (after the window bundle adjustment) and the frame
/// it was taken at.
struct KeyframePose {
  size_t frame_index = 0;
  double timestamp = 0;
  int segment = 0;
  geometry::Pose T_world_cam = geometry::Pose::Identity();
};
/// The keyframes' poses as a trajectory (keyframes.tum).
io::Trajectory keyframe_trajectory(const std::vector<KeyframePose>& keyframes);
/// The tracked frames, each placed where its tracked pose relative to its keyframe (the last
/// one of its map segment taken at or before it) puts it from that keyframe's final pose: the
/// trajectory with the bundle adjustment's corrections carried to every frame (how ORB-SLAM3
/// writes its trajectory files). A frame before its segment's first keyframe keeps its pose.
io::Trajectory keyframe_anchored_trajectory(const std::vector<FrameRecord>& records,
                                            std::vector<KeyframePose> keyframes);
void write_trajectory_tum(const io::Trajectory& trajectory, const std::filesystem::path& path);

/// ASCII PLY: one vertex per map point (grey) and two per line segment (red),
/// and an `edge` element joining each line's two vertices (MeshLab, CloudCompare).
void write_map_ply(const MapData& map, const std::filesystem::path& path);

void write_json(const nlohmann::json& json, const std::filesystem::path& path);

}  // namespace pllvo::vo
