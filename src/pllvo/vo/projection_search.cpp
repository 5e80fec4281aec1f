#include "pllvo/vo/projection_search.h"

#include <cmath>
#include <limits>
#include <set>

#include <opencv2/core.hpp>

namespace pllvo::vo {
namespace {

struct Proposal {
  Id point = kNoId;
  double distance = std::numeric_limits<double>::infinity();
};

// The descriptor of the point's newest observation (the newest look at its patch).
cv::Mat newest_descriptor(const MapData& map, const MapPoint& point) {
  const Keyframe* newest = nullptr;
  int index = -1;
  for (const auto& o : point.observations) {
    auto kf = map.keyframes.find(o.keyframe);
    if (kf == map.keyframes.end() || o.index < 0 || o.index >= kf->second.features.descriptors.rows) continue;
    if (!newest || kf->second.id > newest->id) newest = &kf->second, index = o.index;
  }
  return newest ? newest->features.descriptors.row(index) : cv::Mat();
}

}  // namespace

std::vector<Id> search_by_projection(const MapData& map, const std::vector<Id>& keyframes, const Pinhole& camera,
                                     const geometry::Pose& T_world_cam, const PointFeatures& features,
                                     const std::vector<Id>& ids, const ProjectionSearchConfig& config) {
  const size_t n = features.size();
  std::vector<Proposal> best(n);
  if (!config.enabled || n == 0 || features.descriptors.rows != static_cast<int>(n)) return std::vector<Id>(n, kNoId);

  const std::set<Id> taken(ids.begin(), ids.end());
  std::set<Id> candidates;
  for (Id k : keyframes) {
    auto kf = map.keyframes.find(k);
    if (kf == map.keyframes.end()) continue;
    for (Id p : kf->second.point_ids)
      if (p != kNoId && !taken.count(p)) candidates.insert(p);
  }

  const bool binary = features.binary();
  const int norm = binary ? cv::NORM_HAMMING : cv::NORM_L2;
  const double limit = binary ? config.max_hamming : config.max_float_distance;
  const double radius2 = config.radius_px * config.radius_px;
  const geometry::Pose T_cam_world = T_world_cam.inverse();
  for (Id pid : candidates) {
    auto it = map.points.find(pid);
    if (it == map.points.end()) continue;
    Eigen::Vector2d uv;
    if (!camera.project(T_cam_world * it->second.position, uv) || !camera.inside(uv)) continue;
    const cv::Mat descriptor = newest_descriptor(map, it->second);
    if (descriptor.empty() || descriptor.type() != features.descriptors.type() ||
        descriptor.cols != features.descriptors.cols)
      continue;
    double d1 = std::numeric_limits<double>::infinity(), d2 = d1;
    int nearest = -1;
    for (size_t i = 0; i < n; ++i) {
      if (ids[i] != kNoId) continue;
      const double dx = features.points[i].x - uv.x(), dy = features.points[i].y - uv.y();
      if (dx * dx + dy * dy > radius2) continue;
      const double d = cv::norm(descriptor, features.descriptors.row(static_cast<int>(i)), norm);
      if (d < d1)
        d2 = d1, d1 = d, nearest = static_cast<int>(i);
      else if (d < d2)
        d2 = d;
    }
    if (nearest < 0 || d1 > limit || (std::isfinite(d2) && d1 >= config.ratio * d2)) continue;
    if (d1 < best[nearest].distance) best[nearest] = {pid, d1};
  }
  std::vector<Id> found(n, kNoId);
  for (size_t i = 0; i < n; ++i) found[i] = best[i].point;
  return found;
}

}  // namespace pllvo::vo
