#include "pllvo/vo/line_mapper.h"

#include <algorithm>
#include <cmath>
#include <set>

#include <spdlog/spdlog.h>

#include "pllvo/features/lines/cross_constraint.h"

namespace pllvo::vo {
namespace {

/// A tracked line and a detection are the same edge when they are this close.
constexpr double kSameLineAngleDeg = 3.0;
constexpr double kSameLineDistancePx = 2.0;

/// Largest distance (pixels) of the two projected endpoints of a map line to a detected line,
/// accepted when associating the detection with that map line.
constexpr double kLineGatePx = 6.0;

double overlap_along(const lines::LineSegment& a, const lines::LineSegment& b) {
  const double s = lines::project_along(b.start, a), e = lines::project_along(b.end, a);
  const double lo = std::max(0.0, std::min(s, e)), hi = std::min(a.length(), std::max(s, e));
  return hi - lo;
}

}  // namespace

Segment2d to_segment2d(const lines::LineSegment& s) { return {s.start, s.end}; }

lines::LineSegment to_line_segment(const Segment2d& s, int id) { return lines::LineSegment(s.a, s.b, id); }

LineMapper::LineMapper(const lines::LinesConfig& lines, const geometry::LineTriangulationConfig& triangulation,
                       const Pinhole& camera)
    : config_(lines),
      triangulation_(triangulation),
      camera_(camera),
      detector_(lines.detector),
      associator_(lines.associator) {}

std::vector<lines::LineSegment> LineMapper::detect(const cv::Mat& image) { return constrain(detector_.detect(image)); }

std::vector<lines::LineSegment> LineMapper::constrain(std::vector<lines::LineSegment> segments) const {
  if (config_.cross_constraint.enabled) segments = lines::apply_cross_constraint(segments, config_.cross_constraint);
  return segments;
}

LinePlan LineMapper::plan(const cv::Mat& image, const geometry::Pose& T_world_cam,
                          const std::vector<TrackedLine>& tracked, const Keyframe* previous,
                          const std::vector<lines::PointMatch>& point_matches, const Map& map,
                          const cv::Mat& right, double baseline, std::optional<double> min_plane_angle_deg,
                          const std::vector<lines::LineSegment>* detections) {
  LinePlan plan;
  plan.segments = detections ? constrain(*detections) : detect(image);
  const size_t m = plan.segments.size();
  if (config_.associator.use_descriptors && m > 0) plan.descriptors = lines::compute_lbd_descriptors(image, plan.segments);
  plan.ids.assign(m, kNoId);
  plan.origins.assign(m, Observation{});
  plan.previous.assign(m, Observation{});
  plan.triangulated.assign(m, std::nullopt);
  if (m == 0) return plan;

  // 1. Lines tracked into the keyframe keep their identity: the closest detection on the same edge.
  struct Pair {
    double score;
    int track, line;
  };
  std::vector<Pair> pairs;
  const double max_angle = kSameLineAngleDeg * M_PI / 180.0;
  for (int t = 0; t < static_cast<int>(tracked.size()); ++t) {
    const auto& tl = tracked[t].segment;
    if (tracked[t].line == kNoId && tracked[t].origin.keyframe == kNoId) continue;
    for (int j = 0; j < static_cast<int>(m); ++j) {
      const auto& d = plan.segments[j];
      if (lines::acute_angle(tl, d) > max_angle) continue;
      const double ds = std::abs(lines::signed_line_distance(d.start, tl)),
                   de = std::abs(lines::signed_line_distance(d.end, tl));
      if (std::max(ds, de) > kSameLineDistancePx || overlap_along(tl, d) <= 0) continue;
      pairs.push_back({ds + de, t, j});
    }
  }
  std::sort(pairs.begin(), pairs.end(), [](const Pair& a, const Pair& b) { return a.score < b.score; });
  std::vector<char> track_used(tracked.size(), 0);
  std::set<Id> used_ids;
  for (const auto& p : pairs) {
    const TrackedLine& t = tracked[p.track];
    if (track_used[p.track] || plan.ids[p.line] != kNoId || plan.origins[p.line].keyframe != kNoId) continue;
    if (t.line != kNoId && used_ids.count(t.line)) continue;
    track_used[p.track] = 1;
    if (t.line != kNoId) {
      plan.ids[p.line] = t.line;
      used_ids.insert(t.line);
    } else {
      plan.origins[p.line] = t.origin;
      if (t.last.keyframe != t.origin.keyframe) plan.previous[p.line] = t.last;
    }
    ++plan.from_tracks;
  }

  // 2. The rest through the previous keyframe: point matches vote, LBD helps.
  if (previous && !previous->lines.empty()) {
    std::vector<lines::LineSegment> prev_segments;
    for (const auto& s : previous->lines) prev_segments.push_back(to_line_segment(s));
    const bool descriptors = !plan.descriptors.empty() && previous->line_descriptors.rows == static_cast<int>(prev_segments.size());
    const auto matches = associator_.associate(prev_segments, plan.segments, point_matches,
                                               descriptors ? previous->line_descriptors : cv::Mat(),
                                               descriptors ? plan.descriptors : cv::Mat());
    for (const auto& mt : matches) {
      if (plan.ids[mt.b] != kNoId || plan.origins[mt.b].keyframe != kNoId) continue;
      const Id lid = previous->line_ids[mt.a];
      if (lid != kNoId) {
        if (used_ids.count(lid)) continue;
        plan.ids[mt.b] = lid;
        used_ids.insert(lid);
      } else {
        plan.origins[mt.b] = previous->line_origins[mt.a];
        if (previous->line_origins[mt.a].keyframe != previous->id) plan.previous[mt.b] = {previous->id, mt.a};
      }
      ++plan.from_association;
    }
  }

  // 3. Map lines must project onto their detection; candidates are triangulated.
  const geometry::Pose T_cam_world = T_world_cam.inverse();
  struct View {
    geometry::Pose T_world_cam;
    Segment2d segment;
  };
  std::vector<std::vector<View>> views(m);
  map.read([&](const MapData& md) {
    for (size_t j = 0; j < m; ++j) {
      if (plan.ids[j] != kNoId) {
        auto it = md.lines.find(plan.ids[j]);
        Eigen::Vector2d ps, pe;
        if (it == md.lines.end() || !camera_.project(T_cam_world * it->second.p, ps) ||
            !camera_.project(T_cam_world * it->second.q, pe) ||
            std::abs(lines::signed_line_distance(ps, plan.segments[j])) > kLineGatePx ||
            std::abs(lines::signed_line_distance(pe, plan.segments[j])) > kLineGatePx)
          plan.ids[j] = kNoId;
        continue;
      }
      for (const Observation& o : {plan.origins[j], plan.previous[j]}) {
        if (o.keyframe == kNoId) continue;
        auto kf = md.keyframes.find(o.keyframe);
        if (kf == md.keyframes.end() || o.index < 0 || o.index >= static_cast<int>(kf->second.lines.size())) continue;
        views[j].push_back({kf->second.T_world_cam, kf->second.lines[o.index]});
      }
    }
  });
  geometry::LineTriangulationConfig two_view = triangulation_;
  if (min_plane_angle_deg) two_view.min_plane_angle_deg = *min_plane_angle_deg;
  for (size_t j = 0; j < m; ++j) {
    if (plan.ids[j] != kNoId) continue;
    const auto& s = plan.segments[j];
    for (const View& v : views[j]) {  // the origin first: the widest baseline
      const auto t = geometry::triangulate_line(v.T_world_cam, camera_.normalised(v.segment.a),
                                                camera_.normalised(v.segment.b), T_world_cam,
                                                camera_.normalised(s.start), camera_.normalised(s.end), two_view);
      if (!t.ok()) continue;
      plan.triangulated[j] = t.segment_world;
      break;
    }
  }
  if (!right.empty() && baseline > 0) triangulate_stereo(image, right, baseline, T_world_cam, plan);
  if (spdlog::should_log(spdlog::level::debug)) {
    int mapped = 0, candidates = 0, triangulated = 0;
    for (size_t j = 0; j < m; ++j) {
      mapped += plan.ids[j] != kNoId;
      candidates += plan.ids[j] == kNoId && !views[j].empty();
      triangulated += plan.triangulated[j].has_value();
    }
    spdlog::debug("line plan: {} detected, {} from tracks, {} from the previous keyframe; {} map lines kept, {} "
                  "candidates with earlier views, {} triangulated ({} by stereo)",
                  m, plan.from_tracks, plan.from_association, mapped, candidates, triangulated, plan.from_stereo);
  }
  return plan;
}

void LineMapper::triangulate_stereo(const cv::Mat& image, const cv::Mat& right, double baseline,
                                    const geometry::Pose& T_world_cam, LinePlan& plan) {
  const size_t m = plan.segments.size();
  std::vector<lines::LineSegment> left;
  std::vector<int> index;  // plan index per left line to match
  for (size_t j = 0; j < m; ++j)
    if (plan.ids[j] == kNoId && !plan.triangulated[j]) left.push_back(plan.segments[j]), index.push_back(static_cast<int>(j));
  if (left.empty()) return;
  const auto right_segments = detect(right);
  if (right_segments.empty()) return;
  cv::Mat left_desc, right_desc;
  if (config_.associator.use_descriptors) {
    left_desc = lines::compute_lbd_descriptors(image, left);
    right_desc = lines::compute_lbd_descriptors(right, right_segments);
  }
  const geometry::Pose T_world_right = T_world_cam * T_left_right(baseline);
  geometry::LineTriangulationConfig stereo = triangulation_;
  stereo.min_plane_angle_deg = config_.stereo.min_plane_angle_deg;
  const auto stereo_matches = lines::match_stereo_lines(left, right_segments, left_desc, right_desc, config_.stereo);
  for (const auto& mt : stereo_matches) {
    const auto& l = left[mt.a];
    const auto& r = right_segments[mt.b];
    const auto t = geometry::triangulate_line(T_world_cam, camera_.normalised(l.start), camera_.normalised(l.end),
                                              T_world_right, camera_.normalised(r.start), camera_.normalised(r.end),
                                              stereo);
    if (!t.ok()) continue;
    plan.triangulated[index[mt.a]] = t.segment_world;
    ++plan.from_stereo;
  }
}

int LineMapper::commit(MapData& map, Id kf, const LinePlan& plan) {
  int created = 0;
  auto link_earlier = [&](Id lid, const Observation& o) {
    if (o.keyframe == kNoId) return;
    auto k = map.keyframes.find(o.keyframe);
    if (k != map.keyframes.end() && o.index < static_cast<int>(k->second.line_ids.size()) &&
        k->second.line_ids[o.index] == kNoId)
      map.observe_line(lid, o.keyframe, o.index);
  };
  for (size_t j = 0; j < plan.segments.size(); ++j) {
    const int idx = static_cast<int>(j);
    if (plan.ids[j] != kNoId && map.lines.count(plan.ids[j])) {
      map.observe_line(plan.ids[j], kf, idx);
    } else if (plan.triangulated[j]) {
      const Id lid = map.add_line(plan.triangulated[j]->start, plan.triangulated[j]->end);
      link_earlier(lid, plan.origins[j]);
      link_earlier(lid, plan.previous[j]);
      map.observe_line(lid, kf, idx);
      ++created;
    }
  }
  return created;
}

}  // namespace pllvo::vo
