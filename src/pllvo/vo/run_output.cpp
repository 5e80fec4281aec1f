#include "pllvo/vo/run_output.h"

#include <algorithm>
#include <atomic>
#include <fstream>
#include <iomanip>
#include <random>
#include <sstream>
#include <unordered_map>

#include <unistd.h>

#include "pllvo/common/error.h"

namespace pllvo::vo {
namespace fs = std::filesystem;

namespace {

fs::path temporary_beside(const fs::path& path) {
  // The process id and a counter make concurrent writers (threads, processes) distinct.
  static std::atomic<unsigned> counter{0};
  std::ostringstream name;
  name << "." << path.filename().string() << ".tmp-" << ::getpid() << "-" << counter++;
  return path.parent_path() / name.str();
}

}  // namespace

void write_atomically(const fs::path& path, const std::function<void(std::ostream&)>& write) {
  std::error_code ec;
  if (!path.parent_path().empty()) fs::create_directories(path.parent_path(), ec);
  if (ec) throw InputError(path, "cannot create the folder: " + ec.message());
  const fs::path tmp = temporary_beside(path);
  try {
    {
      std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
      if (!out) throw InputError(path, "cannot write the file");
      write(out);
      out.flush();
      if (!out) throw InputError(path, "write failed");
    }
    fs::rename(tmp, path, ec);
    if (ec) throw InputError(path, "cannot rename the temporary file: " + ec.message());
  } catch (...) {
    fs::remove(tmp, ec);
    throw;
  }
}

std::vector<LostInterval> lost_intervals(const std::vector<FrameRecord>& records) {
  std::vector<LostInterval> out;
  for (const auto& r : records) {
    if (r.tracked) continue;
    if (!out.empty() && out.back().last_frame + 1 == r.index) {
      out.back().last_frame = r.index;
      out.back().last_time = r.timestamp;
    } else {
      out.push_back({r.index, r.index, r.timestamp, r.timestamp});
    }
  }
  return out;
}

io::Trajectory tracked_trajectory(const std::vector<FrameRecord>& records) {
  io::Trajectory traj;
  for (const auto& r : records)
    if (r.tracked) traj.push_back(r.timestamp, r.T_world_cam);
  return traj;
}

io::Trajectory keyframe_trajectory(const std::vector<KeyframePose>& keyframes) {
  io::Trajectory traj;
  for (const KeyframePose& kf : keyframes) traj.push_back(kf.timestamp, kf.T_world_cam);
  return traj;
}

io::Trajectory keyframe_anchored_trajectory(const std::vector<FrameRecord>& records,
                                            std::vector<KeyframePose> keyframes) {
  std::unordered_map<size_t, const FrameRecord*> by_index;
  for (const auto& r : records) by_index[r.index] = &r;
  std::sort(keyframes.begin(), keyframes.end(),
            [](const KeyframePose& a, const KeyframePose& b) { return a.frame_index < b.frame_index; });
  io::Trajectory traj;
  for (const auto& r : records) {
    if (!r.tracked) continue;
    geometry::Pose T = r.T_world_cam;
    auto it = std::upper_bound(keyframes.begin(), keyframes.end(), r.index,
                               [](size_t index, const KeyframePose& k) { return index < k.frame_index; });
    if (it != keyframes.begin()) {
      const KeyframePose& kf = *std::prev(it);
      const auto at = by_index.find(kf.frame_index);
      if (kf.segment == r.segment && at != by_index.end() && at->second->tracked && at->second->segment == r.segment)
        T = kf.T_world_cam * at->second->T_world_cam.inverse() * r.T_world_cam;
    }
    traj.push_back(r.timestamp, T);
  }
  return traj;
}

void write_trajectory_tum(const io::Trajectory& trajectory, const fs::path& path) {
  write_atomically(path, [&](std::ostream& out) {
    out << std::setprecision(17);
    for (size_t i = 0; i < trajectory.size(); ++i) {
      const auto& T = trajectory.poses[i];
      const Eigen::Quaterniond q(T.linear());
      const Eigen::Vector3d t = T.translation();
      out << trajectory.stamps[i] << ' ' << t.x() << ' ' << t.y() << ' ' << t.z() << ' ' << q.x() << ' '
          << q.y() << ' ' << q.z() << ' ' << q.w() << '\n';
    }
  });
}

void write_map_ply(const MapData& map, const fs::path& path) {
  write_atomically(path, [&](std::ostream& out) {
    const size_t n_vertices = map.points.size() + 2 * map.lines.size();
    out << "ply\nformat ascii 1.0\ncomment pllvo map: points (grey), line segments (red edges)\n"
        << "element vertex " << n_vertices << "\nproperty float x\nproperty float y\nproperty float z\n"
        << "property uchar red\nproperty uchar green\nproperty uchar blue\n"
        << "element edge " << map.lines.size() << "\nproperty int vertex1\nproperty int vertex2\n"
        << "end_header\n";
    out << std::setprecision(9);
    for (const auto& [id, p] : map.points)
      out << p.position.x() << ' ' << p.position.y() << ' ' << p.position.z() << " 200 200 200\n";
    for (const auto& [id, l] : map.lines) {
      out << l.p.x() << ' ' << l.p.y() << ' ' << l.p.z() << " 255 40 40\n";
      out << l.q.x() << ' ' << l.q.y() << ' ' << l.q.z() << " 255 40 40\n";
    }
    const size_t first = map.points.size();
    for (size_t i = 0; i < map.lines.size(); ++i)
      out << first + 2 * i << ' ' << first + 2 * i + 1 << '\n';
  });
}

void write_json(const nlohmann::json& json, const fs::path& path) {
  write_atomically(path, [&](std::ostream& out) { out << json.dump(2) << '\n'; });
}

}  // namespace pllvo::vo
