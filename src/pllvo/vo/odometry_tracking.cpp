// Odometry: the per-frame tracking of points and lines, the pose, the keyframe geometry the
// tracker reads (line angles, candidate parallax).
#include "pllvo/vo/odometry.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>

#include <opencv2/imgproc.hpp>
#include <spdlog/spdlog.h>

#include "pllvo/common/error.h"
#include "pllvo/common/statistics.h"
#include "pllvo/features/lines/cross_constraint.h"
#include "pllvo/nn/runtime.h"
#include "pllvo/vo/odometry_detail.h"

namespace pllvo::vo {
namespace {

/// Re-detection baseline (pipeline.line_tracking: redetect): each expected segment takes the
/// detection on the same image line (direction within kRedetectAngleDeg, both detected
/// endpoints within kRedetectDistancePx of the expected line, overlapping along it), closest
/// first, one to one.
constexpr double kRedetectAngleDeg = 5.0;

constexpr double kRedetectDistancePx = 6.0;

std::vector<int> associate_by_position(const std::vector<lines::LineSegment>& expected,
                                       const std::vector<lines::LineSegment>& detections) {
  struct Pair {
    double score;
    int e, d;
  };
  std::vector<Pair> pairs;
  const double max_angle = kRedetectAngleDeg * M_PI / 180.0;
  for (int e = 0; e < static_cast<int>(expected.size()); ++e) {
    const auto& x = expected[e];
    for (int d = 0; d < static_cast<int>(detections.size()); ++d) {
      const auto& y = detections[d];
      if (lines::acute_angle(x, y) > max_angle) continue;
      const double ds = std::abs(lines::signed_line_distance(y.start, x)),
                   de = std::abs(lines::signed_line_distance(y.end, x));
      if (std::max(ds, de) > kRedetectDistancePx) continue;
      const double s0 = lines::project_along(y.start, x), s1 = lines::project_along(y.end, x);
      if (std::min(x.length(), std::max(s0, s1)) - std::max(0.0, std::min(s0, s1)) <= 0) continue;
      pairs.push_back({ds + de + (x.midpoint() - y.midpoint()).norm() * 0.1, e, d});
    }
  }
  std::sort(pairs.begin(), pairs.end(), [](const Pair& a, const Pair& b) { return a.score < b.score; });
  std::vector<int> out(expected.size(), -1);
  std::vector<char> used(detections.size(), 0);
  for (const auto& p : pairs)
    if (out[p.e] < 0 && !used[p.d]) out[p.e] = p.d, used[p.d] = 1;
  return out;
}

}  // namespace

using namespace odometry_detail;

bool Odometry::track_or_restart(const io::Frame& frame, const cv::Mat& left, const cv::Mat& right,
                                const ImagePyramid& pyramid, FrameRecord& record) {
  if (track(frame, left, right, pyramid, record)) return true;
  handle_lost(frame.timestamp);
  if (!config_.pose.stereo_restart_at_once || !metric()) return false;
  std::optional<DetectedKeyframe> detected;
  if (state_ == TrackingState::kTracking) {
    // Coasting on the tracks left sometimes gets the pose back a frame later in the same map,
    // so the map is only given up for a restart that this frame places in it. The start
    // below reuses the features detected for the try.
    if (config_.pose.relocalise_min_inliers <= 0) return false;
    // Live input (run.wait_when_starving off) makes no try: its detection and matching would
    // hold the tracking thread for 200-500 ms (the frames arriving meanwhile dropped), and the
    // new map's first keyframe, on the worker, is relocalised in this one all the same.
    if (!config_.run.wait_when_starving) return false;
    worker_.wait_idle();
    worker_.rethrow_if_failed();
    const KeyframeJob job = make_keyframe_job(frame, left, right, pyramid, KeyframeReason::kNone);
    detected = processor_.detect_keyframe(job);
    if (!processor_.relocalise_in_segment(job, *detected)) return false;
    reset();
  }
  bool relocalised = false;
  if (initialize(frame, left, right, pyramid, std::move(detected), &relocalised) && relocalised) {
    stats_.add_count("restarts_relocalised_at_once");
    return true;  // the relocalised pose is this frame's
  }
  return false;
}

bool Odometry::track(const io::Frame& frame, const cv::Mat& left, const cv::Mat& right,
                     const ImagePyramid& pyramid, FrameRecord& record) {
  // After failed frames the last pose is that many steps back (a held map's is too old to extrapolate).
  geometry::Pose T_world_pred = T_world_work_;
  if (config_.pose.use_motion_prior && has_velocity_)
    for (int step = 0; step <= (holding_map() ? 0 : lost_frames_); ++step) T_world_pred = T_world_pred * velocity_;
  const geometry::Pose T_pred_world = T_world_pred.inverse();

  std::vector<Eigen::Vector3d> positions(tracks_.size());
  std::vector<unsigned char> known(tracks_.size(), 0);
  PoseExtras extras;
  map_.read([&](const MapData& m) {
    for (size_t i = 0; i < tracks_.size(); ++i) {
      auto it = m.points.find(tracks_[i].point);
      if (it == m.points.end()) continue;
      positions[i] = it->second.position, known[i] = 1;
    }
  });
  // known == 2: a candidate at its provisional position (pose.provisional_points).
  if (uses_provisional_points())
    for (size_t i = 0; i < tracks_.size(); ++i)
      if (!known[i] && tracks_[i].point == kNoId && tracks_[i].provisional)
        positions[i] = *tracks_[i].provisional, known[i] = 2;
  std::vector<cv::Point2f> from, predicted;
  for (size_t i = 0; i < tracks_.size(); ++i) {
    from.push_back(tracks_[i].px);
    predicted.push_back(klt_seed(known[i] ? &positions[i] : nullptr, tracks_[i].px, T_pred_world));
  }
  TrackResult tr;
  {
    ScopedTimer t(stats_, "klt");
    tr = tracker_.track_with_contrast_fallback(previous_pyramid_, pyramid, from, &predicted);
    if (tr.contrast_retried) stats_.add_count("klt_contrast_fallbacks");
  }
  follow_corners(pyramid, T_pred_world);
  stats_.add_count("klt_rejected.lk", tr.rejected.lk);
  stats_.add_count("klt_rejected.border", tr.rejected.border);
  stats_.add_count("klt_rejected.forward_backward", tr.rejected.forward_backward);
  stats_.add_count("klt_rejected.appearance", tr.rejected.appearance);

  // Lines: predicted from their 3-D segment when they have one, followed by line optical flow.
  std::vector<LineMeasurement> line_measurements;
  std::vector<size_t> measured_lines;  // index in line_tracks_ per measurement
  if (use_lines_ && !line_tracks_.empty()) {
    ScopedTimer t(stats_, "line_tracking");
    std::vector<lines::LineSegment> predicted_lines;
    std::vector<std::optional<std::pair<Eigen::Vector3d, Eigen::Vector3d>>> ends(line_tracks_.size());
    map_.read([&](const MapData& m) {
      for (size_t i = 0; i < line_tracks_.size(); ++i) {
        auto it = m.lines.find(line_tracks_[i].line);
        if (it != m.lines.end()) ends[i] = std::make_pair(it->second.p, it->second.q);
      }
    });
    for (size_t i = 0; i < line_tracks_.size(); ++i) {
      lines::LineSegment p = line_tracks_[i].segment;
      Eigen::Vector2d a, b;
      if (ends[i] && camera_.project(T_pred_world * ends[i]->first, a) &&
          camera_.project(T_pred_world * ends[i]->second, b) && camera_.inside(a) && camera_.inside(b)) {
        // The tracked segment's extent, moved onto the predicted image line.
        const lines::LineSegment image_line(a, b);
        const double sa = lines::project_along(p.start, image_line), sb = lines::project_along(p.end, image_line);
        if (image_line.length() > 1) p.start = image_line.at(sa / image_line.length()), p.end = image_line.at(sb / image_line.length());
      }
      predicted_lines.push_back(p);
    }
    const size_t mapped_before = count_mapped_lines(line_tracks_);
    const bool plain = plain_frame();
    if (plain) stats_.add_count("plain_scene_line_frames");
    const std::vector<lines::LineSegment>* detections =
        redetect_lines_ && !line_tracks_.empty() ? &frame_lines(pyramid.image, frame.index) : nullptr;
    line_tracks_ = track_lines(previous_pyramid_, pyramid, line_tracks_, plain, &predicted_lines, detections);
    spdlog::debug("frame {}: line flow kept {} of {} mapped lines ({} lines in all)", frame.index,
                  count_mapped_lines(line_tracks_), mapped_before, line_tracks_.size());
    if (config_.pose.use_lines) {
      map_.read([&](const MapData& m) {
        for (size_t i = 0; i < line_tracks_.size(); ++i) {
          auto it = m.lines.find(line_tracks_[i].line);
          if (it == m.lines.end()) continue;
          line_measurements.push_back({it->second.p, it->second.q, to_segment2d(line_tracks_[i].segment)});
          measured_lines.push_back(i);
        }
      });
    }
  }

  std::vector<size_t> which;
  std::vector<Eigen::Vector3d> pts;
  std::vector<Eigen::Vector2d> px;
  for (size_t i = 0; i < tracks_.size(); ++i) {
    if (!tr.ok[i] || !known[i]) continue;
    which.push_back(i);
    pts.push_back(positions[i]);
    px.push_back(to_eigen(tr.points[i]));
  }
  // The tracker's own corners join a starving frame as provisional points do.
  const size_t first_corner = pts.size();
  std::vector<size_t> corner_of;  // corners_ index of pts[first_corner + k]
  if (uses_provisional_points())
    for (size_t i = 0; i < corners_.size(); ++i)
      if (corners_[i].position) {
        corner_of.push_back(i);
        pts.push_back(*corners_[i].position);
        px.push_back(to_eigen(corners_[i].px));
      }

  std::vector<DirectionSegment> dir_segments;
  if (use_directions_) {
    ScopedTimer t(stats_, "direction_lines");
    dir_segments = direction_segments(pyramid.image, frame.index);
    extras.directions = direction_observations(dir_segments, T_pred_world.linear());
    extras.direction_weight = config_.directions.weight;
    stats_.add_count("direction_observations", static_cast<long long>(extras.directions.size()));
    spdlog::debug("frame {}: {} of {} detected segments on {} known directions", frame.index, extras.directions.size(),
                  dir_segments.size(), directions_.directions().size());
  }

  PoseEstimate estimate;
  {
    ScopedTimer t(stats_, "pose");
    std::optional<geometry::Pose> predicted;
    if (config_.pose.use_motion_prior && has_velocity_) predicted = T_world_pred;
    estimate = estimate_pose(camera_, pts, px, line_measurements, predicted, config_.geometry, config_.backend, extras);
    if (!estimate.ok && config_.pose.use_motion_prior && config_.pose.min_inliers_with_prior > 0) {
      // Too few points for PnP (a textureless stretch): the constant-velocity prediction
      // carries the pose while a few observations (points and lines) still agree with it.
      // Right after a start there is no velocity yet: T_world_pred is the last pose (no motion).
      backend::BackendConfig weak = config_.backend;
      weak.pose_refiner.min_inliers = config_.pose.min_inliers_with_prior;
      estimate = estimate_pose(camera_, pts, px, line_measurements, T_world_pred, config_.geometry, weak, extras);
      if (estimate.ok) stats_.add_count("prior_supported_poses");
    }
    const bool by_frame_motion = !estimate.ok;
    if (by_frame_motion) estimate = pose_from_frame_motion(frame.index, from, tr, which, line_measurements.size());
    frame_motion_run_ = estimate.ok && by_frame_motion ? frame_motion_run_ + 1 : 0;
    if (estimate.ok && by_frame_motion) {
      stats_.add_count("frame_motion_poses");
      stats_.add_sample("frame_motion_run", frame_motion_run_);  // its max: the longest run in a row
    }
  }

  // Keep the tracks that survived KLT (and, on success, the pose's inlier test); candidates
  // (no map point yet) only need KLT: one at a provisional position that the pose refuses
  // stays a candidate without it.
  std::vector<TrackedPoint> kept;
  int map_inliers = 0, provisional_inliers = 0;
  for (size_t k = 0; k < which.size(); ++k) {
    const bool provisional = known[which[k]] == 2;
    const bool inlier = !estimate.ok || estimate.point_inliers[k];
    if (!inlier && !provisional) continue;
    TrackedPoint tp = tracks_[which[k]];
    tp.px = tr.points[which[k]];
    if (!inlier) tp.provisional.reset();
    if (estimate.ok && inlier) ++(provisional ? provisional_inliers : map_inliers);
    kept.push_back(tp);
  }
  for (size_t i = 0; i < tracks_.size(); ++i) {
    if (known[i] || tracks_[i].point != kNoId || !tr.ok[i]) continue;
    TrackedPoint tp = tracks_[i];
    tp.px = tr.points[i];
    kept.push_back(tp);
  }
  tracks_ = std::move(kept);
  int corner_inliers = 0;
  for (size_t k = 0; k < corner_of.size() && estimate.ok; ++k) {
    const size_t e = first_corner + k;  // beyond a frame-motion estimate's inliers: not part of it
    if (e < estimate.point_inliers.size() && estimate.point_inliers[e]) ++corner_inliers;
    else corners_[corner_of[k]].position.reset();
  }
  if (estimate.ok) {
    // Lines whose 3-D segment disagrees with the pose lose the link (their track may be off).
    std::vector<char> drop(line_tracks_.size(), 0);
    for (size_t k = 0; k < measured_lines.size(); ++k)
      if (!estimate.line_inliers[k]) drop[measured_lines[k]] = 1;
    std::vector<TrackedLine> kept_lines;
    for (size_t i = 0; i < line_tracks_.size(); ++i)
      if (!drop[i]) kept_lines.push_back(line_tracks_[i]);
    line_tracks_ = std::move(kept_lines);
  }
  spdlog::debug("frame {}: {} map points followed, {} pose inliers, {} tracks kept; {} of {} 3-D lines agree",
                frame.index, pts.size(), estimate.ok ? estimate.num_point_inliers : 0, tracks_.size(),
                estimate.ok ? estimate.num_line_inliers : 0, line_measurements.size());

  if (!estimate.ok) {
    spdlog::debug("frame {}: pose failed ({} tracked points)", frame.index, pts.size());
    return false;
  }
  const geometry::Pose T_world_cur = estimate.T_world_cam;
  frame_directions_.clear();
  if (use_directions_) {
    // The segments at the estimated pose: a keyframe of this frame takes them to the window.
    const Eigen::Matrix3d R_cam_world = T_world_cur.linear().transpose();
    frame_directions_ = direction_observations(dir_segments, R_cam_world);
    const int added = directions_.discover(dir_segments, R_cam_world, camera_.focal());
    if (added > 0) {
      stats_.add_count("directions_added", added);
      const Eigen::Vector3d& d = directions_.directions().back();
      spdlog::debug("frame {}: {} new directions ({} known), last {:.4f} {:.4f} {:.4f}", frame.index, added,
                    directions_.directions().size(), d.x(), d.y(), d.z());
    }
  }
  velocity_ = T_world_work_.inverse() * T_world_cur;
  // After lost frames the step spans several frames: do not extrapolate it.
  has_velocity_ = lost_frames_ == 0;
  T_world_work_ = T_world_cur;
  lost_frames_ = 0;
  remember_position(frame.index, T_world_cur.translation());
  // The map's own points: provisional ones do not stand in for a keyframe's.
  record.tracked_points = map_inliers;
  record.tracked_lines = estimate.num_line_inliers;
  if (provisional_inliers > 0) {
    stats_.add_count("provisional_point_frames");
    stats_.add_sample("provisional_point_inliers", provisional_inliers);
  }
  if (corner_inliers > 0) stats_.add_sample("frame_corner_inliers", corner_inliers);
  if (makes_provisional_points()) triangulate_candidates();
  refresh_corners(pyramid, right, map_inliers);

  maybe_make_keyframe(frame, left, right, pyramid, map_inliers);
  return true;
}

bool Odometry::uses_provisional_points() const {
  // The plain starving threshold, not the noisy frames' (a monocular map waits for every
  // keyframe there): with enough map points, provisional ones only add their depth's doubt.
  return makes_provisional_points() && count_mapped(tracks_) < config_.run.starving_points;
}

cv::Point2f Odometry::klt_seed(const Eigen::Vector3d* position, const cv::Point2f& px,
                               const geometry::Pose& T_pred_world) const {
  // A held map's last pose is frames old: the track's own position is the better seed.
  Eigen::Vector2d uv;
  if (position && !holding_map() && camera_.project(T_pred_world * *position, uv) && camera_.inside(uv))
    return {static_cast<float>(uv.x()), static_cast<float>(uv.y())};
  return px;
}

void Odometry::triangulate_candidates() {
  ScopedTimer t(stats_, "provisional_points");
  // The keyframe views under the map's lock, the triangulation after it (the worker writes the map).
  std::vector<TrackViews> views(tracks_.size());
  map_.read([&](const MapData& m) {
    for (size_t i = 0; i < tracks_.size(); ++i) {
      const TrackedPoint& tp = tracks_[i];
      if (tp.point != kNoId || tp.origin.keyframe == kNoId) continue;
      views[i].add(m, tp.origin);
      if (tp.last.keyframe != tp.origin.keyframe) views[i].add(m, tp.last);
    }
  });
  for (size_t i = 0; i < tracks_.size(); ++i) {
    TrackedPoint& tp = tracks_[i];
    tp.provisional.reset();
    if (views[i].px.empty()) continue;
    views[i].add(T_world_work_, to_eigen(tp.px));
    tp.provisional = triangulate_point(camera_, views[i].T_world_cam, views[i].px, config_.geometry.point_triangulation);
  }
}

PoseEstimate Odometry::pose_from_frame_motion(size_t frame_index, const std::vector<cv::Point2f>& from,
                                              const TrackResult& tr, const std::vector<size_t>& map_tracks,
                                              size_t num_lines) const {
  const PoseConfig& c = config_.pose;
  PoseEstimate est;
  // The previous frame must have its pose: the motion is measured from it.
  if (metric() || c.mono_frame_motion_min_inliers <= 0 || !has_velocity_ || lost_frames_ > 0 ||
      frame_motion_run_ >= c.mono_frame_motion_max_frames)
    return est;
  std::vector<Eigen::Vector2d> xy0, xy1;
  std::vector<int> match_of_track(from.size(), -1);
  for (size_t i = 0; i < from.size(); ++i) {
    if (!tr.ok[i]) continue;
    match_of_track[i] = static_cast<int>(xy0.size());
    xy0.push_back(camera_.normalised(to_eigen(from[i])));
    xy1.push_back(camera_.normalised(to_eigen(tr.points[i])));
  }
  geometry::RelativeMotionLimits limits;
  limits.min_inliers = c.mono_frame_motion_min_inliers;
  limits.max_rotation_change_deg = c.mono_frame_motion_max_rotation_change_deg;
  limits.max_translation_change_deg = c.mono_frame_motion_max_translation_change_deg;
  limits.translation_prior_sigma_deg = c.mono_frame_motion_translation_sigma_deg;
  const geometry::RelativeMotion m = geometry::estimate_relative_motion(
      xy0, xy1, camera_.focal(), velocity_.inverse(), limits, config_.geometry.two_view);
  spdlog::debug("frame {}: motion from the previous frame {}: {} of {} tracks fit, {:.1f} deg from the last "
                "rotation, {:.0f} deg from the last direction{}{}{}",
                frame_index, m.ok ? "taken" : "refused", m.num_inliers, xy0.size(), m.rotation_from_expected_deg,
                m.translation_from_expected_deg, m.translation_kept ? " (direction kept)" : "", m.ok ? "" : ": ",
                m.failure);
  if (!m.ok) return est;
  geometry::Pose T_cur_prev = m.T_cam1_cam0;
  T_cur_prev.translation() *= velocity_.translation().norm();
  est.ok = true;
  est.T_world_cam = T_world_work_ * T_cur_prev.inverse();
  for (size_t i : map_tracks) {
    const bool inlier = match_of_track[i] >= 0 && m.inliers[match_of_track[i]];
    est.point_inliers.push_back(inlier);
    est.num_point_inliers += inlier;
  }
  // The map's lines were not part of this estimate: keep their tracks for the next frame.
  est.line_inliers.assign(num_lines, 1);
  return est;
}

std::vector<TrackedLine> Odometry::track_lines(const ImagePyramid& from, const ImagePyramid& to,
                                               const std::vector<TrackedLine>& lines,
                                               bool plain,
                                               const std::vector<lines::LineSegment>* predicted,
                                               const std::vector<lines::LineSegment>* detected) const {
  if (lines.empty()) return {};
  std::vector<lines::LineSegment> segments;
  segments.reserve(lines.size());
  for (const auto& l : lines) segments.push_back(l.segment);
  if (redetect_lines_) {
    if (!detected) return {};
    stats_.add_count("line_redetections");
    const std::vector<lines::LineSegment> detections =
        config_.lines.cross_constraint.enabled ? lines::apply_cross_constraint(*detected, config_.lines.cross_constraint)
                                               : *detected;
    const auto assignment = associate_by_position(predicted ? *predicted : segments, detections);
    std::vector<TrackedLine> kept;
    for (size_t i = 0; i < lines.size(); ++i) {
      if (assignment[i] < 0) continue;
      TrackedLine l = lines[i];
      l.segment = detections[assignment[i]];
      kept.push_back(l);
    }
    return kept;
  }
  const auto tracks = (plain ? plain_line_tracker_ : line_tracker_).track(from.flow, to.flow, segments, predicted);
  std::vector<TrackedLine> kept;
  for (size_t i = 0; i < tracks.size(); ++i) {
    if (tracks[i].status != lines::TrackStatus::Tracked) {
      stats_.add_count(std::string("line_rejected.") + lines::to_string(tracks[i].status));
      continue;
    }
    TrackedLine l = lines[i];
    l.segment = tracks[i].line;
    kept.push_back(l);
  }
  return kept;
}

const std::vector<lines::LineSegment>& Odometry::frame_lines(const cv::Mat& image, size_t frame_index) {
  if (!detected_lines_ || detected_lines_frame_ != frame_index) {
    detected_lines_ = line_detector_.detect(image);
    detected_lines_frame_ = frame_index;
  }
  return *detected_lines_;
}

std::vector<DirectionSegment> Odometry::direction_segments(const cv::Mat& image, size_t frame_index) {
  // Detected afresh in every frame: line flow loses most lines in noisy dim images (its
  // samples fail the fit), where the rotation needs them most.
  std::vector<DirectionSegment> out;
  for (const auto& l : frame_lines(image, frame_index))
    out.push_back({camera_.normalised(l.start), camera_.normalised(l.end), l.length()});
  return out;
}

std::vector<backend::PoseDirectionObservation> Odometry::direction_observations(
    const std::vector<DirectionSegment>& segments, const Eigen::Matrix3d& R_cam_world) const {
  std::vector<backend::PoseDirectionObservation> out;
  const auto& known = directions_.directions();
  if (static_cast<int>(known.size()) < config_.directions.min_known) return out;
  const std::vector<int> dir = directions_.associate(segments, R_cam_world, camera_.focal());
  for (size_t i = 0; i < dir.size(); ++i)
    if (dir[i] >= 0) out.push_back({known[dir[i]], segments[i].start, segments[i].end});
  return out;
}

bool Odometry::plain_frame() const {
  const int below = config_.plain_scene.max_tracked_points;
  return below > 0 && count_mapped(tracks_) < below;
}

void Odometry::set_reference_lines(const std::vector<TrackedLine>& lines) {
  std::vector<lines::LineSegment> segments;
  for (const auto& l : lines) segments.push_back(l.segment);
  reference_angles_ = lines::overlap_angle_set(segments, config_.lines.overlap_angles);
}

std::optional<double> Odometry::line_angle_distance() const {
  if (!use_lines_) return std::nullopt;
  std::vector<lines::LineSegment> segments;
  for (const auto& l : line_tracks_) segments.push_back(l.segment);
  const auto current = lines::overlap_angle_set(segments, config_.lines.overlap_angles);
  const size_t min_angles = static_cast<size_t>(config_.keyframes.line_min_angles);
  if (current.size() < min_angles || reference_angles_.size() < min_angles) return std::nullopt;
  return lines::overlap_angle_distance(reference_angles_, current);
}

// ---------------------------------------------------------------- failure

}  // namespace pllvo::vo
