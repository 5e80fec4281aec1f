#include "pllvo/vo/keyframe_processor.h"

#include <algorithm>
#include <cmath>
#include <set>

#include <spdlog/spdlog.h>

namespace pllvo::vo {
namespace {

Eigen::Vector2d to_eigen(const cv::Point2f& p) { return {p.x, p.y}; }

}  // namespace

KeyframeProcessor::KeyframeProcessor(const VoConfig& config, const Pinhole& camera, double baseline, Map& map,
                                     RunStats& stats)
    : config_(config),
      camera_(camera),
      baseline_(baseline),
      map_(map),
      stats_(stats),
      frontend_(make_point_frontend(config.frontend)),
      matcher_(make_keyframe_matcher(config.mapping, config.frontend.type)),
      frontend_name_(frontend_->name()),
      stereo_tracker_(config.klt) {}

PointFeatures KeyframeProcessor::detect(const cv::Mat& image) {
  ScopedTimer t(stats_, "kf_detect");
  return frontend_->detect(image);
}

void KeyframeProcessor::start_segment() {
  ++segment_;
  segment_keyframes_.clear();
}

std::vector<std::optional<Eigen::Vector3d>> KeyframeProcessor::stereo_points(const KeyframeJob& job,
                                                                            const PointFeatures& features,
                                                                            const std::vector<Id>& ids) {
  ScopedTimer t(stats_, "kf_stereo");
  std::vector<std::optional<Eigen::Vector3d>> out(features.size());
  if (job.right.empty()) return out;
  std::vector<int> which;
  std::vector<cv::Point2f> pts;
  for (int i = 0; i < static_cast<int>(features.size()); ++i)
    if (ids[i] == kNoId) which.push_back(i), pts.push_back(features.points[i]);
  if (pts.empty()) return out;
  const ImagePyramid left = job.left_pyramid.empty() ? stereo_tracker_.build_pyramid(job.left) : job.left_pyramid;
  const ImagePyramid right = stereo_tracker_.build_pyramid(job.right);
  const TrackResult tr = stereo_tracker_.track(left, right, pts);
  for (size_t k = 0; k < which.size(); ++k) {
    if (!tr.ok[k]) continue;
    if (std::abs(tr.points[k].y - pts[k].y) > config_.init.stereo_max_epipolar_px) continue;
    out[which[k]] = triangulate_stereo(camera_, baseline_, to_eigen(pts[k]), to_eigen(tr.points[k]),
                                       config_.init.min_depth_m, config_.init.max_depth_m);
  }
  return out;
}

KeyframeResult KeyframeProcessor::process(const KeyframeJob& job) {
  ScopedTimer total(stats_, "kf_total");
  KeyframeResult result;
  result.frame_index = job.frame_index;
  PointFeatures features;
  {
    ScopedTimer t(stats_, "kf_detect");
    std::vector<cv::Point2f> tracked;
    tracked.reserve(job.tracks.size());
    for (const auto& tp : job.tracks) tracked.push_back(tp.px);
    features = frontend_->detect(job.left, tracked);
  }
  const size_t n = features.size();
  std::vector<Id> ids(n, kNoId);
  std::vector<Observation> origins(n);  // kNoId: the keyframe itself (set when added)
  std::vector<int> prev_index(n, -1);   // matched feature in the previous keyframe
  for (size_t i = 0; i < n; ++i) {
    const int s = features.source.empty() ? -1 : features.source[i];
    if (s < 0) continue;
    const TrackedPoint& tp = job.tracks[s];
    if (tp.point != kNoId)
      ids[i] = tp.point;
    else
      origins[i] = tp.origin;
  }

  const bool has_prev = !job.first && !segment_keyframes_.empty();
  if (has_prev) {
    ScopedTimer t(stats_, "kf_match");
    Keyframe prev;
    map_.read([&](const MapData& m) { prev = m.keyframes.at(segment_keyframes_.back()); });
    const auto matches = matcher_->match(prev.features, features, job.left.size());
    result.matches = static_cast<int>(matches.size());
    std::set<Id> used(ids.begin(), ids.end());
    for (const auto& mt : matches) {
      prev_index[mt.b] = mt.a;
      const Id pid = prev.point_ids[mt.a];
      if (ids[mt.b] != kNoId) continue;
      if (pid != kNoId) {
        if (!used.count(pid)) ids[mt.b] = pid, used.insert(pid);
      } else if (origins[mt.b].keyframe == kNoId) {
        origins[mt.b] = prev.origins[mt.a];
      }
    }
  }

  // Keep only associations that agree with the keyframe pose (a wrong match or a drifted
  // track would otherwise pull the bundle adjustment).
  std::vector<Eigen::Vector3d> positions(n);
  struct OriginView {
    geometry::Pose T_world_cam;
    Eigen::Vector2d px;
    bool ok = false;
  };
  std::vector<OriginView> origin_views(n);
  map_.read([&](const MapData& m) {
    for (size_t i = 0; i < n; ++i) {
      if (ids[i] != kNoId) {
        auto it = m.points.find(ids[i]);
        if (it == m.points.end()) {
          ids[i] = kNoId;
          continue;
        }
        positions[i] = it->second.position;
      } else if (origins[i].keyframe != kNoId) {
        auto kf = m.keyframes.find(origins[i].keyframe);
        if (kf == m.keyframes.end()) continue;
        origin_views[i] = {kf->second.T_world_cam, to_eigen(kf->second.features.points[origins[i].index]), true};
      }
    }
  });
  const geometry::Pose T_cam_world = job.T_world_cam.inverse();
  const double gate = 3.0 * config_.mapping.max_reprojection_px;
  for (size_t i = 0; i < n; ++i) {
    if (ids[i] == kNoId) continue;
    Eigen::Vector2d uv;
    if (!camera_.project(T_cam_world * positions[i], uv) || (uv - to_eigen(features.points[i])).norm() > gate)
      ids[i] = kNoId;
  }

  std::vector<std::optional<Eigen::Vector3d>> stereo(n);
  if (!job.right.empty()) stereo = stereo_points(job, features, ids);
  std::vector<std::optional<Eigen::Vector3d>> triangulated(n);
  {
    ScopedTimer t(stats_, "kf_triangulate");
    for (size_t i = 0; i < n; ++i) {
      if (ids[i] != kNoId || stereo[i] || !origin_views[i].ok) continue;
      triangulated[i] = triangulate_point(camera_, origin_views[i].T_world_cam, job.T_world_cam,
                                          origin_views[i].px, to_eigen(features.points[i]), config_.mapping);
    }
  }
  if (job.first) {
    const auto made = std::count_if(stereo.begin(), stereo.end(), [](const auto& p) { return p.has_value(); });
    if (made < config_.init.stereo_min_points) return result;
  }

  const Id prev_id = has_prev ? segment_keyframes_.back() : kNoId;
  Id kid = kNoId;
  int new_points = 0;
  map_.write([&](MapData& m) {
    Keyframe kf;
    kf.frame_index = job.frame_index;
    kf.timestamp = job.timestamp;
    kf.T_world_cam = job.T_world_cam;
    kf.reason = job.reason;
    kf.segment = segment_;
    kf.features = features;
    kf.origins = origins;
    kid = m.add_keyframe(std::move(kf));
    for (size_t i = 0; i < n; ++i) {
      const int idx = static_cast<int>(i);
      if (ids[i] != kNoId && m.points.count(ids[i])) {
        m.observe_point(ids[i], kid, idx);
      } else if (stereo[i]) {
        const Id pid = m.add_point(job.T_world_cam * *stereo[i]);
        m.observe_point(pid, kid, idx);
        ids[i] = pid;
        ++new_points;
      } else if (triangulated[i]) {
        const Id pid = m.add_point(*triangulated[i]);
        const Observation& o = origins[i];
        if (m.keyframes.at(o.keyframe).point_ids[o.index] == kNoId) m.observe_point(pid, o.keyframe, o.index);
        if (prev_id != kNoId && prev_id != o.keyframe && prev_index[i] >= 0 &&
            m.keyframes.at(prev_id).point_ids[prev_index[i]] == kNoId)
          m.observe_point(pid, prev_id, prev_index[i]);
        m.observe_point(pid, kid, idx);
        ids[i] = pid;
        ++new_points;
      }
    }
  });
  segment_keyframes_.push_back(kid);
  result.ok = true;
  result.keyframe = kid;
  result.new_points = new_points;
  stats_.add_count("keyframes");
  stats_.add_count("keyframes." + to_string(job.reason));
  stats_.add_sample("kf_matches", result.matches);
  stats_.add_sample("kf_new_points", new_points);

  {
    ScopedTimer t(stats_, "kf_ba");
    const size_t window = static_cast<size_t>(config_.mapping.window_keyframes);
    std::vector<Id> ids_window(segment_keyframes_.end() - std::min(window, segment_keyframes_.size()),
                               segment_keyframes_.end());
    const int fixed = std::max(1, std::min<int>(config_.mapping.fixed_keyframes, static_cast<int>(ids_window.size()) - 1));
    if (ids_window.size() >= 2)
      map_.write([&](MapData& m) { return bundle_adjust_window(m, camera_, ids_window, fixed, config_.mapping); });
  }

  map_.read([&](const MapData& m) {
    const auto& kf = m.keyframes.at(kid);
    for (size_t i = 0; i < kf.point_ids.size(); ++i)
      result.tracks.push_back({kf.features.points[i], kf.point_ids[i], kf.origins[i]});
  });
  spdlog::debug("keyframe {} (frame {}, {}): {} features, {} matches, {} new points, {} tracked", kid,
                job.frame_index, to_string(job.reason), n, result.matches, new_points, result.tracks.size());
  return result;
}

KeyframeResult KeyframeProcessor::initialize_mono(const KeyframeJob& reference, const PointFeatures& ref_features,
                                                  const std::vector<std::optional<Eigen::Vector3d>>& ref_points_world,
                                                  KeyframeJob second, const std::vector<cv::Point2f>& second_px) {
  second.tracks.clear();
  Id kid = kNoId;
  map_.write([&](MapData& m) {
    Keyframe kf;
    kf.frame_index = reference.frame_index;
    kf.timestamp = reference.timestamp;
    kf.T_world_cam = reference.T_world_cam;
    kf.reason = KeyframeReason::kInitialization;
    kf.segment = segment_;
    kf.features = ref_features;
    kid = m.add_keyframe(std::move(kf));
    for (size_t i = 0; i < ref_features.size(); ++i) {
      if (i >= second_px.size() || std::isnan(second_px[i].x)) continue;
      TrackedPoint tp;
      tp.px = second_px[i];
      tp.origin = {kid, static_cast<int>(i)};
      if (i < ref_points_world.size() && ref_points_world[i]) {
        tp.point = m.add_point(*ref_points_world[i]);
        m.observe_point(tp.point, kid, static_cast<int>(i));
      }
      second.tracks.push_back(tp);
    }
  });
  segment_keyframes_.push_back(kid);
  stats_.add_count("keyframes");
  stats_.add_count("keyframes." + to_string(KeyframeReason::kInitialization));
  second.reason = KeyframeReason::kInitialization;
  return process(second);
}

}  // namespace pllvo::vo
