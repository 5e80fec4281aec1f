#include "pllvo/vo/keyframe_processor.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include <spdlog/spdlog.h>

#include "pllvo/vo/stereo_depth.h"

namespace pllvo::vo {
namespace {

Eigen::Vector2d to_eigen(const cv::Point2f& p) { return {p.x, p.y}; }

/// Pixel pairs of the same points in the previous keyframe and this one, for line
/// association: shared map points, candidates tracked from it, and descriptor matches.
std::vector<lines::PointMatch> point_matches_with(const Keyframe& prev, bool has_prev, const PointFeatures& features,
                                                  const std::vector<Id>& ids, const std::vector<Observation>& previous,
                                                  const std::vector<PointMatch>& matches) {
  std::vector<lines::PointMatch> out;
  if (!has_prev) return out;
  std::map<Id, int> index_of;
  for (size_t a = 0; a < prev.point_ids.size(); ++a)
    if (prev.point_ids[a] != kNoId) index_of[prev.point_ids[a]] = static_cast<int>(a);
  std::vector<char> paired(features.size(), 0);
  for (size_t b = 0; b < features.size(); ++b) {
    int a = -1;
    if (ids[b] != kNoId) {
      auto it = index_of.find(ids[b]);
      if (it != index_of.end()) a = it->second;
    } else if (previous[b].keyframe == prev.id) {
      a = previous[b].index;
    }
    if (a < 0) continue;
    out.push_back({to_eigen(prev.features.points[a]), to_eigen(features.points[b])});
    paired[b] = 1;
  }
  for (const auto& mt : matches)
    if (!paired[mt.b]) out.push_back({to_eigen(prev.features.points[mt.a]), to_eigen(features.points[mt.b])});
  return out;
}

}  // namespace

KeyframeProcessor::KeyframeProcessor(const VoConfig& config, const Pinhole& camera, double baseline, Map& map,
                                     RunStats& stats, bool depth_images)
    : config_(config),
      camera_(camera),
      baseline_(baseline),
      depth_images_(depth_images),
      map_(map),
      stats_(stats),
      frontend_(make_point_frontend(config.frontend)),
      matcher_(make_keyframe_matcher(config.mapping, frontend_->name())),
      frontend_name_(frontend_->name()),
      klt_(config.klt) {
  if (config_.pipeline.lines)
    line_mapper_ = std::make_unique<LineMapper>(config_.lines, config_.geometry.line_triangulation, camera_);
}

std::optional<double> KeyframeProcessor::line_plane_angle(const KeyframeJob& job, size_t features) const {
  const auto& plain = config_.plain_scene;
  if (baseline_ > 0 || plain.mono_line_min_plane_angle_deg <= 0 ||
      static_cast<int>(features) >= plain.mono_max_keyframe_features || job.image_noise >= config_.run.noisy_frame_noise)
    return std::nullopt;
  return plain.mono_line_min_plane_angle_deg;
}

backend::BundleAdjustmentConfig KeyframeProcessor::window_ba_config() const {
  backend::BundleAdjustmentConfig ba = config_.backend.bundle_adjustment;
  // RGB-D: the virtual pair has no offset to estimate.
  if (depth_images_) ba.stereo_offset_sigma_px = 0;
  if (baseline_ > 0) return ba;
  // A monocular map has a free scale as well: a second fixed keyframe pins it.
  ba.num_fixed_oldest = std::max(2, ba.num_fixed_oldest);
  return ba;
}

PointFeatures KeyframeProcessor::detect(const cv::Mat& image) {
  ScopedTimer t(stats_, "kf_detect");
  return drop_edge_points(image, frontend_->detect(image));
}

PointFeatures KeyframeProcessor::drop_edge_points(const cv::Mat& image, PointFeatures features) {
  const double min_ratio = config_.frontend.min_corner_ratio;
  if (min_ratio <= 0) return features;
  std::vector<int> keep;
  for (int i = 0; i < static_cast<int>(features.size()); ++i) {
    const bool tracked = !features.source.empty() && features.source[i] >= 0;
    if (tracked || corner_ratio(image, features.points[i], config_.klt.window_px) >= min_ratio) keep.push_back(i);
  }
  stats_.add_count("edge_points_dropped", static_cast<int>(features.size() - keep.size()));
  return features.select(keep);
}

std::vector<std::optional<Eigen::Vector3d>> KeyframeProcessor::stereo_points(const KeyframeJob& job,
                                                                            const PointFeatures& features,
                                                                            const std::vector<Id>& ids,
                                                                            std::vector<cv::Point2f>& right_px) {
  if (depth_images_) return depth_points(job, features, ids, right_px);
  ScopedTimer t(stats_, "kf_stereo");
  std::vector<std::optional<Eigen::Vector3d>> out(features.size());
  right_px.assign(features.size(), cv::Point2f(NAN, NAN));
  if (job.right.empty() || features.empty()) return out;
  const ImagePyramid left = job.left_pyramid.empty() ? klt_.build_pyramid(job.left) : job.left_pyramid;
  StereoDepths sd = stereo_depths(klt_, left, job.left, job.right, features.points, camera_, baseline_,
                                  stereo_offset_px_, stereo_row_match(config_), config_.geometry.stereo);
  right_px = std::move(sd.right_px);
  for (size_t i = 0; i < features.size(); ++i)
    if (ids[i] == kNoId) out[i] = sd.points[i];
  if (sd.row_rejects > 0) stats_.add_count("stereo_row_rejects", sd.row_rejects);
  const auto& lk = sd.lk_rejected;
  spdlog::debug("frame {}: stereo depth for {} of {} features; lost: right-image LK {} (status {}, border {}, "
                "forward-backward {}, appearance {}), row refinement {}, depth check {}", job.frame_index, sd.matched,
                features.size(), lk.lk + lk.border + lk.forward_backward + lk.appearance, lk.lk, lk.border,
                lk.forward_backward, lk.appearance, sd.row_rejects, sd.depth_rejects);
  return out;
}

std::vector<std::optional<Eigen::Vector3d>> KeyframeProcessor::depth_points(const KeyframeJob& job,
                                                                           const PointFeatures& features,
                                                                           const std::vector<Id>& ids,
                                                                           std::vector<cv::Point2f>& right_px) {
  ScopedTimer t(stats_, "kf_depth");
  std::vector<std::optional<Eigen::Vector3d>> out(features.size());
  StereoDepths sd = depth_image_depths(job.depth, features.points, camera_, baseline_, config_.depth,
                                       config_.geometry.stereo);
  right_px = std::move(sd.right_px);
  for (size_t i = 0; i < features.size(); ++i)
    if (ids[i] == kNoId) out[i] = sd.points[i];
  if (sd.edge_rejects > 0) stats_.add_count("depth_edge_rejects", sd.edge_rejects);
  if (!job.depth.empty())
    spdlog::debug("frame {}: depth for {} of {} features ({} on depth edges)", job.frame_index, sd.matched,
                  features.size(), sd.edge_rejects);
  return out;
}

bool KeyframeProcessor::stereo_start_ok(const std::vector<std::optional<Eigen::Vector3d>>& stereo,
                                        int stereo_lines) const {
  // A stereo line constrains the pose like a point does (two residuals); PnP still needs its
  // minimum of points to seed the pose of the frames that follow.
  const auto points = std::count_if(stereo.begin(), stereo.end(), [](const auto& p) { return p.has_value(); });
  const bool ok = points >= config_.geometry.pnp.min_inliers &&
                  points + stereo_lines >= config_.init.stereo_min_points;
  if (!ok) spdlog::debug("stereo start: {} points and {} lines, not enough", points, stereo_lines);
  return ok;
}

geometry::Pose KeyframeProcessor::current_pose(const KeyframeJob& job) {
  // The tracker estimated the pose against the map as it was then; the bundle adjustments
  // that ran since moved points and keyframes. Triangulating against the refreshed map keeps
  // new points consistent with it (otherwise the scale of a monocular map drifts).
  if (job.first) return job.T_world_cam;
  std::vector<Eigen::Vector3d> pts;
  std::vector<Eigen::Vector2d> px;
  map_.read([&](const MapData& m) {
    for (const auto& t : job.tracks) {
      auto it = m.points.find(t.point);
      if (it == m.points.end()) continue;
      pts.push_back(it->second.position);
      px.push_back(to_eigen(t.px));
    }
  });
  const PoseEstimate e = estimate_pose(camera_, pts, px, {}, job.T_world_cam, config_.geometry, config_.backend);
  return e.ok ? e.T_world_cam : job.T_world_cam;
}

std::vector<PointMatch> KeyframeProcessor::match_previous(const Keyframe& prev, const KeyframeJob& job,
                                                          const PointFeatures& features, int& linked) {
  linked = 0;
  if (!config_.mapping.match_untracked_only) return matcher_->match(prev.features, features, job.left.size());
  // A feature of the new keyframe is linked when KLT carried it from the previous keyframe.
  std::vector<char> linked_new(features.size(), 0), linked_prev(prev.features.size(), 0);
  for (size_t i = 0; i < features.size(); ++i) {
    const int s = features.source.empty() ? -1 : features.source[i];
    if (s < 0) continue;
    const Observation& last = job.tracks[static_cast<size_t>(s)].last;
    if (last.keyframe != prev.id || last.index < 0 || last.index >= static_cast<int>(linked_prev.size())) continue;
    linked_new[i] = linked_prev[static_cast<size_t>(last.index)] = 1;
  }
  linked = static_cast<int>(std::count(linked_new.begin(), linked_new.end(), 1));
  return match_unflagged(*matcher_, prev.features, linked_prev, features, linked_new, job.left.size());
}

void KeyframeProcessor::reattach_by_projection(const geometry::Pose& T_world_cam, const PointFeatures& features,
                                                std::vector<Id>& ids, std::vector<Observation>& origins,
                                                std::vector<Observation>& previous) {
  const auto& config = config_.mapping.projection_search;
  if (!config.enabled) return;
  ScopedTimer t(stats_, "kf_projection_search");
  const size_t count = std::min(static_cast<size_t>(config.keyframes), segment_keyframes_.size());
  const std::vector<Id> recent(segment_keyframes_.end() - static_cast<std::ptrdiff_t>(count), segment_keyframes_.end());
  const std::vector<Id> found = map_.read([&](const MapData& m) {
    return search_by_projection(m, recent, camera_, T_world_cam, features, ids, config);
  });
  int reattached = 0;
  for (size_t i = 0; i < found.size(); ++i) {
    if (found[i] == kNoId) continue;
    ids[i] = found[i];
    origins[i] = previous[i] = Observation{};  // a point now: no longer a candidate
    ++reattached;
  }
  stats_.add_sample("kf_reattached_points", reattached);
}

void KeyframeProcessor::remember_image(Id keyframe, const KeyframeJob& job) {
  if (baseline_ > 0 || !config_.mapping.mono_align_to_origin || job.left.empty()) return;
  keyframe_images_[keyframe] = klt_.reference_levels(job.left, config_.mapping.mono_align_levels);
  while (keyframe_images_.size() > static_cast<size_t>(config_.mapping.mono_align_cache_keyframes))
    keyframe_images_.erase(keyframe_images_.begin());
}

void KeyframeProcessor::align_to_origins(const KeyframeJob& job, PointFeatures& features, const std::vector<Id>& ids,
                                         std::vector<Observation>& origins, std::vector<Observation>& previous) {
  if (job.left_pyramid.empty()) return;
  ScopedTimer t(stats_, "kf_align");
  std::map<Id, std::vector<size_t>> by_origin;  // one LK call per origin keyframe
  for (size_t i = 0; i < features.size(); ++i)
    if (ids[i] == kNoId && origins[i].keyframe != kNoId && keyframe_images_.count(origins[i].keyframe))
      by_origin[origins[i].keyframe].push_back(i);
  int aligned = 0, dropped = 0;
  for (const auto& [kf, which] : by_origin) {
    std::vector<cv::Point2f> from, to;
    map_.read([&](const MapData& m) {
      const auto it = m.keyframes.find(kf);
      if (it == m.keyframes.end()) return;
      for (size_t i : which) {
        from.push_back(it->second.features.points[origins[i].index]);
        to.push_back(features.points[i]);
      }
    });
    if (from.empty()) continue;
    const auto ok = klt_.align(keyframe_images_.at(kf), job.left_pyramid, from, to, config_.mapping.mono_align_levels,
                               config_.mapping.mono_align_max_shift_px);
    for (size_t k = 0; k < which.size(); ++k) {
      const size_t i = which[k];
      if (ok[k]) {
        features.points[i] = to[k];
        ++aligned;
      } else {
        // Not the origin's point, or too far from it: the track starts again from this keyframe.
        origins[i] = previous[i] = Observation{};
        ++dropped;
      }
    }
  }
  stats_.add_count("aligned_candidates", aligned);
  stats_.add_count("alignment_dropped", dropped);
}

DetectedKeyframe KeyframeProcessor::detect_keyframe(const KeyframeJob& job) {
  ScopedTimer t(stats_, "kf_detect");
  std::vector<cv::Point2f> tracked;
  tracked.reserve(job.tracks.size());
  for (const auto& tp : job.tracks) tracked.push_back(tp.px);
  DetectedKeyframe detected;
  detected.features = drop_edge_points(job.left, frontend_->detect(job.left, tracked));
  detected.detect_ms = t.elapsed_ms();
  return detected;
}

KeyframeResult KeyframeProcessor::process(const KeyframeJob& original_job, DetectedKeyframe detected) {
  ScopedTimer total(stats_, "kf_total", detected.detect_ms);
  PointFeatures features = std::move(detected.features);
  KeyframeJob job = original_job;
  job.T_world_cam = current_pose(original_job);
  KeyframeResult result;
  result.frame_index = job.frame_index;
  const size_t n = features.size();
  std::vector<Id> ids(n, kNoId);
  std::vector<Observation> origins(n);   // first keyframe observation (kNoId: this keyframe)
  std::vector<Observation> previous(n);  // latest earlier keyframe observation, when newer than the origin
  for (size_t i = 0; i < n; ++i) {
    const int s = features.source.empty() ? -1 : features.source[i];
    if (s < 0) continue;
    const TrackedPoint& tp = job.tracks[s];
    if (tp.point != kNoId) {
      ids[i] = tp.point;
    } else {
      origins[i] = tp.origin;
      if (tp.last.keyframe != tp.origin.keyframe) previous[i] = tp.last;
    }
  }

  const bool has_prev = !job.first && !segment_keyframes_.empty();
  Keyframe prev;
  std::vector<PointMatch> matches;
  if (has_prev) {
    ScopedTimer t(stats_, "kf_match");
    map_.read([&](const MapData& m) { prev = m.keyframes.at(segment_keyframes_.back()); });
    int linked = 0;
    matches = match_previous(prev, job, features, linked);
    // Correspondences with the previous keyframe, whether KLT or the matcher found them.
    result.matches = linked + static_cast<int>(matches.size());
    stats_.add_sample("kf_matcher_matches", static_cast<double>(matches.size()));
    if (const auto effort = matcher_->last_effort()) {
      stats_.add_sample("matcher_layers_run", effort->layers_run);
      stats_.add_sample("matcher_pruned_share", effort->pruned_share);
    }
    frontend_->report_matches(result.matches, static_cast<int>(features.size()));
    std::set<Id> used(ids.begin(), ids.end());
    for (const auto& mt : matches) {
      if (ids[mt.b] != kNoId || origins[mt.b].keyframe != kNoId) continue;  // tracked: already known
      const Id pid = prev.point_ids[mt.a];
      if (pid != kNoId) {
        if (!used.count(pid)) ids[mt.b] = pid, used.insert(pid);
      } else {
        origins[mt.b] = prev.origins[mt.a];
        if (prev.origins[mt.a].keyframe != prev.id) previous[mt.b] = {prev.id, mt.a};
      }
    }
  }

  if (has_prev) reattach_by_projection(job.T_world_cam, features, ids, origins, previous);
  const bool align = baseline_ <= 0 && config_.mapping.mono_align_to_origin &&
                     job.image_noise >= config_.mapping.mono_align_min_noise;
  if (align) align_to_origins(job, features, ids, origins, previous);

  // Map points and the earlier views of candidates, read once.
  std::vector<Eigen::Vector3d> positions(n);
  std::vector<TrackViews> views(n);
  map_.read([&](const MapData& m) {
    for (size_t i = 0; i < n; ++i) {
      if (ids[i] != kNoId) {
        auto it = m.points.find(ids[i]);
        if (it == m.points.end())
          ids[i] = kNoId;
        else
          positions[i] = it->second.position;
      } else if (origins[i].keyframe != kNoId) {
        views[i].add(m, origins[i]);
        if (previous[i].keyframe != kNoId) views[i].add(m, previous[i]);
      }
    }
  });
  // Keep only associations that agree with the keyframe pose (a wrong match or a drifted
  // track would otherwise pull the bundle adjustment).
  const geometry::Pose T_cam_world = job.T_world_cam.inverse();
  const double gate = 3.0 * config_.geometry.point_triangulation.max_reprojection_error_px;
  for (size_t i = 0; i < n; ++i) {
    if (ids[i] == kNoId) continue;
    Eigen::Vector2d uv;
    if (!camera_.project(T_cam_world * positions[i], uv) || (uv - to_eigen(features.points[i])).norm() > gate)
      ids[i] = kNoId;
  }

  std::vector<std::optional<Eigen::Vector3d>> stereo(n);
  std::vector<cv::Point2f> right_px;
  if (baseline_ > 0) stereo = stereo_points(job, features, ids, right_px);
  std::vector<std::optional<Eigen::Vector3d>> triangulated(n);
  {
    ScopedTimer t(stats_, "kf_triangulate");
    for (size_t i = 0; i < n; ++i) {
      if (ids[i] != kNoId || stereo[i] || views[i].px.empty()) continue;
      TrackViews v = views[i];
      v.add(job.T_world_cam, to_eigen(features.points[i]));
      triangulated[i] = triangulate_point(camera_, v.T_world_cam, v.px, config_.geometry.point_triangulation);
    }
  }
  // Stereo lines: on every keyframe with lines.stereo, else on plain ones (plain_scene), which
  // leaves starts to the points. Without them the points alone decide a stereo start: no line
  // work on a failed one.
  const int plain_below = config_.plain_scene.max_keyframe_features;
  const bool plain = !job.first && plain_below > 0 && static_cast<int>(n) < plain_below;
  const bool stereo_lines = line_mapper_ && !job.right.empty() && (config_.lines.stereo.enabled || plain);
  if (plain && stereo_lines) stats_.add_count("plain_scene_keyframes");
  if (job.first && !stereo_lines && !stereo_start_ok(stereo, 0)) return result;
  // A first keyframe has no map points nor candidates yet: its pose is first used from here on
  // (stereo points into the world, lines), so a restart can still be placed in the old map.
  if (job.first && baseline_ > 0) {
    const std::optional<geometry::Pose>& known = detected.relocalised_T_world_cam;  // restart decided on this frame
    if (const auto T = known ? known : relocalise(job, features)) {
      job.T_world_cam = *T, result.relocalised = true;
      stats_.add_count("relocalisations");
    }
  }

  LinePlan line_plan;
  if (line_mapper_) {
    ScopedTimer t(stats_, "kf_lines");
    line_plan = line_mapper_->plan(job.left, job.T_world_cam, job.lines, has_prev ? &prev : nullptr,
                                   point_matches_with(prev, has_prev, features, ids, previous, matches), map_,
                                   stereo_lines ? job.right : cv::Mat(), baseline_, line_plane_angle(job, n),
                                   job.line_detections ? &*job.line_detections : nullptr);
    stats_.add_sample("kf_lines", static_cast<double>(line_plan.segments.size()));
    if (stereo_lines) stats_.add_sample("kf_stereo_lines", line_plan.from_stereo);
  }
  if (job.first && stereo_lines && !stereo_start_ok(stereo, line_plan.from_stereo)) return result;

  Id kid = kNoId;
  int new_points = 0;
  map_.write([&](MapData& m) {
    Keyframe kf;
    for (const auto& l : line_plan.segments) kf.lines.push_back(to_segment2d(l));
    kf.line_origins = line_plan.origins;
    kf.line_descriptors = line_plan.descriptors;
    kf.directions = job.directions;
    kf.frame_index = job.frame_index;
    kf.timestamp = job.timestamp;
    kf.T_world_cam = job.T_world_cam;
    kf.reason = job.reason;
    kf.segment = segment_;
    kf.features = features;
    kf.origins = origins;
    kf.right_points = std::move(right_px);
    kid = m.add_keyframe(std::move(kf));
    // Links an earlier keyframe's feature to a new point unless it already has one.
    auto link_earlier = [&](Id pid, const Observation& o) {
      if (o.keyframe == kNoId) return;
      auto k = m.keyframes.find(o.keyframe);
      if (k != m.keyframes.end() && k->second.point_ids[o.index] == kNoId) m.observe_point(pid, o.keyframe, o.index);
    };
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
        link_earlier(pid, origins[i]);
        link_earlier(pid, previous[i]);
        m.observe_point(pid, kid, idx);
        ids[i] = pid;
        ++new_points;
      }
    }
    result.created_lines = LineMapper::commit(m, kid, line_plan);
  });
  segment_keyframes_.push_back(kid);
  remember_image(kid, job);
  result.ok = true;
  result.keyframe = kid;
  result.T_world_cam = job.T_world_cam;
  result.new_points = new_points;
  stats_.add_count("keyframes");
  stats_.add_count("keyframes." + to_string(job.reason));
  stats_.add_sample("kf_matches", result.matches);
  stats_.add_sample("kf_new_points", new_points);

  {
    ScopedTimer t(stats_, "kf_ba");
    const size_t window = static_cast<size_t>(config_.backend.bundle_adjustment.window_size);
    const std::vector<Id> ids_window(segment_keyframes_.end() - std::min(window, segment_keyframes_.size()),
                                     segment_keyframes_.end());
    const auto ba = bundle_adjust_window(map_, camera_, baseline_, ids_window, config_.mapping.max_anchor_keyframes,
                                         window_ba_config(), config_.directions.ba_weight,
                                         stereo_offset_px_);
    if (ba.ran) {
      if (baseline_ > 0) {
        stats_.add_sample("ba_stereo_offset_px", ba.stereo_offset_px);
        spdlog::debug("frame {}: window BA stereo offset {:.3f} px", job.frame_index, ba.stereo_offset_px);
      }
      stereo_offset_px_ = ba.stereo_offset_px;
      stats_.add_sample("ba_rms_px", ba.final_rms_px);
      stats_.add_count("ba_point_outliers", ba.point_outliers);
      stats_.add_count("ba_line_outliers", ba.line_outliers);
    }
  }
  result.stereo_offset_px = stereo_offset_px_;

  map_.read([&](const MapData& m) {
    const auto& kf = m.keyframes.at(kid);
    result.T_world_cam_adjusted = kf.T_world_cam;
    for (size_t i = 0; i < kf.point_ids.size(); ++i)
      result.tracks.push_back({kf.features.points[i], kf.point_ids[i], kf.origins[i], {kid, static_cast<int>(i)}});
    for (size_t j = 0; j < kf.lines.size(); ++j)
      result.lines.push_back({to_line_segment(kf.lines[j], static_cast<int>(j)), kf.line_ids[j], kf.line_origins[j],
                              {kid, static_cast<int>(j)}});
  });
  stats_.add_sample("kf_new_lines", result.created_lines);
  spdlog::debug("keyframe {} (frame {}, {}): {} features, {} matches, {} new points, {} tracked; {} lines, {} new",
                kid, job.frame_index, to_string(job.reason), n, result.matches, new_points, result.tracks.size(),
                result.lines.size(), result.created_lines);
  return result;
}

}  // namespace pllvo::vo
