#include "pllvo/vo/map.h"

#include <algorithm>

#include "pllvo/common/error.h"

namespace pllvo::vo {

std::optional<FeatureView> MapData::feature_view(const Observation& o) const {
  auto kf = keyframes.find(o.keyframe);
  if (kf == keyframes.end() || o.index < 0 || o.index >= static_cast<int>(kf->second.features.size()))
    return std::nullopt;
  const cv::Point2f& p = kf->second.features.points[o.index];
  return FeatureView{kf->second.T_world_cam, Eigen::Vector2d(p.x, p.y)};
}

void TrackViews::add(const MapData& m, const Observation& o) {
  if (const auto view = m.feature_view(o)) add(view->T_world_cam, view->px);
}

Id MapData::add_keyframe(Keyframe kf) {
  kf.id = next_id++;
  kf.point_ids.resize(kf.features.size(), kNoId);
  kf.line_ids.resize(kf.lines.size(), kNoId);
  kf.line_origins.resize(kf.lines.size());
  for (size_t i = 0; i < kf.line_origins.size(); ++i)
    if (kf.line_origins[i].keyframe == kNoId) kf.line_origins[i] = {kf.id, static_cast<int>(i)};
  kf.origins.resize(kf.features.size());
  for (size_t i = 0; i < kf.origins.size(); ++i)
    if (kf.origins[i].keyframe == kNoId) kf.origins[i] = {kf.id, static_cast<int>(i)};
  const Id id = kf.id;
  keyframes.emplace(id, std::move(kf));
  return id;
}

Id MapData::add_point(const Eigen::Vector3d& position) {
  MapPoint p;
  p.id = next_id++;
  p.position = position;
  const Id id = p.id;
  points.emplace(id, std::move(p));
  return id;
}

Id MapData::add_line(const Eigen::Vector3d& p, const Eigen::Vector3d& q) {
  MapLine l;
  l.id = next_id++;
  l.p = p;
  l.q = q;
  const Id id = l.id;
  lines.emplace(id, std::move(l));
  return id;
}

void MapData::observe_point(Id point, Id kf, int index) {
  auto& k = keyframes.at(kf);
  auto& p = points.at(point);
  if (index < 0 || index >= static_cast<int>(k.point_ids.size()))
    throw InternalError("observe_point: feature index out of range");
  const Id old = k.point_ids[index];
  if (old == point) return;
  if (old != kNoId) {
    auto& o = points.at(old).observations;
    o.erase(std::remove_if(o.begin(), o.end(), [&](const Observation& x) { return x.keyframe == kf; }), o.end());
  }
  k.point_ids[index] = point;
  p.observations.push_back({kf, index});
}

void MapData::observe_line(Id line, Id kf, int index) {
  auto& k = keyframes.at(kf);
  auto& l = lines.at(line);
  if (index < 0 || index >= static_cast<int>(k.line_ids.size()))
    throw InternalError("observe_line: line index out of range");
  k.line_ids[index] = line;
  l.observations.push_back({kf, index});
}

namespace {

template <typename Landmark>
void unlink(std::map<Id, Landmark>& landmarks, std::map<Id, Keyframe>& keyframes, Id id, Id kf, int index,
            std::vector<Id> Keyframe::*ids) {
  auto it = landmarks.find(id);
  if (it == landmarks.end()) return;
  auto& obs = it->second.observations;
  obs.erase(std::remove_if(obs.begin(), obs.end(),
                           [&](const Observation& o) { return o.keyframe == kf && o.index == index; }),
            obs.end());
  auto k = keyframes.find(kf);
  if (k != keyframes.end() && index >= 0 && index < static_cast<int>((k->second.*ids).size()) &&
      (k->second.*ids)[index] == id)
    (k->second.*ids)[index] = kNoId;
  if (obs.empty()) landmarks.erase(it);
}

}  // namespace

void MapData::unobserve_point(Id point, Id kf, int index) { unlink(points, keyframes, point, kf, index, &Keyframe::point_ids); }

void MapData::unobserve_line(Id line, Id kf, int index) { unlink(lines, keyframes, line, kf, index, &Keyframe::line_ids); }

void MapData::erase_point(Id point) {
  auto it = points.find(point);
  if (it == points.end()) return;
  for (const auto& o : it->second.observations) {
    auto kf = keyframes.find(o.keyframe);
    if (kf != keyframes.end() && o.index < static_cast<int>(kf->second.point_ids.size()) &&
        kf->second.point_ids[o.index] == point)
      kf->second.point_ids[o.index] = kNoId;
  }
  points.erase(it);
}

void MapData::erase_line(Id line) {
  auto it = lines.find(line);
  if (it == lines.end()) return;
  for (const auto& o : it->second.observations) {
    auto kf = keyframes.find(o.keyframe);
    if (kf != keyframes.end() && o.index < static_cast<int>(kf->second.line_ids.size()) &&
        kf->second.line_ids[o.index] == line)
      kf->second.line_ids[o.index] = kNoId;
  }
  lines.erase(it);
}

std::vector<Id> MapData::newest_keyframes(size_t n) const {
  std::vector<Id> ids;
  for (auto it = keyframes.rbegin(); it != keyframes.rend() && ids.size() < n; ++it) ids.push_back(it->first);
  std::reverse(ids.begin(), ids.end());
  return ids;
}

void MapData::clear() {
  keyframes.clear();
  points.clear();
  lines.clear();
}

}  // namespace pllvo::vo
