#pragma once
// The sparse map: keyframes with their features, 3-D points, 3-D line segments and the
// observations linking them. Shared by the tracking thread (reads) and the keyframe
// worker (writes), so every access goes through read()/write() under one lock.
#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <vector>

#include <Eigen/Geometry>

#include "pllvo/backend/pose_refiner.h"
#include "pllvo/geometry/pose.h"
#include "pllvo/vo/keyframe_policy.h"
#include "pllvo/vo/point_frontend.h"

namespace pllvo::vo {

using Id = std::int64_t;
constexpr Id kNoId = -1;

/// A 2-D line segment in pixels.
struct Segment2d {
  Eigen::Vector2d a = Eigen::Vector2d::Zero(), b = Eigen::Vector2d::Zero();
};

struct Observation {
  Id keyframe = kNoId;
  int index = -1;  ///< feature (or line) index in that keyframe
};

struct Keyframe {
  Id id = kNoId;
  size_t frame_index = 0;
  double timestamp = 0;
  geometry::Pose T_world_cam = geometry::Pose::Identity();
  KeyframeReason reason = KeyframeReason::kNone;
  int segment = 0;  ///< map segment (increases with every re-initialisation)
  PointFeatures features;          ///< detected on this keyframe (left image)
  std::vector<Id> point_ids;       ///< per feature: its map point, or kNoId
  /// Per feature without a map point: the first keyframe observation of the same point
  /// (through matches), so triangulation can use the widest baseline seen so far.
  std::vector<Observation> origins;
  /// Stereo: per feature, its position in the rectified right image (NaN: no stereo match).
  /// The bundle adjustment uses them as observations of camera 1, which fixes the metric scale.
  std::vector<cv::Point2f> right_points;
  std::vector<Segment2d> lines;    ///< detected line segments (left image)
  std::vector<Id> line_ids;        ///< per line: its map line, or kNoId
  std::vector<Observation> line_origins;  ///< per line without a map line: its first keyframe observation
  cv::Mat line_descriptors;        ///< LBD, one row per line (empty when not computed)
  /// Segments parallel to known directions (directions.*), for the bundle adjustment.
  std::vector<backend::PoseDirectionObservation> directions;
};

/// Where a keyframe saw a feature: the keyframe's pose and the feature's pixel.
struct FeatureView {
  geometry::Pose T_world_cam;
  Eigen::Vector2d px;
};

struct MapPoint {
  Id id = kNoId;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< world frame
  std::vector<Observation> observations;
};

struct MapLine {
  Id id = kNoId;
  Eigen::Vector3d p = Eigen::Vector3d::Zero(), q = Eigen::Vector3d::Zero();  ///< world endpoints
  std::vector<Observation> observations;
};

struct MapData;

/// The views of one feature track with their poses, in step: what triangulate_point takes.
struct TrackViews {
  std::vector<geometry::Pose> T_world_cam;
  std::vector<Eigen::Vector2d> px;
  void add(const geometry::Pose& T, const Eigen::Vector2d& p) { T_world_cam.push_back(T), px.push_back(p); }
  /// Observation `o`'s keyframe view; nothing when that keyframe is gone.
  void add(const MapData& m, const Observation& o);
};

/// Plain data of the map; ids increase in creation order, so std::map keeps that order.
struct MapData {
  std::map<Id, Keyframe> keyframes;
  std::map<Id, MapPoint> points;
  std::map<Id, MapLine> lines;
  Id next_id = 0;

  Id add_keyframe(Keyframe kf);
  Id add_point(const Eigen::Vector3d& position);
  Id add_line(const Eigen::Vector3d& p, const Eigen::Vector3d& q);
  /// Links feature `index` of keyframe `kf` to the point (both directions).
  void observe_point(Id point, Id kf, int index);
  void observe_line(Id line, Id kf, int index);
  /// Unlinks one observation (both directions); a point or line left without observations
  /// is erased.
  void unobserve_point(Id point, Id kf, int index);
  void unobserve_line(Id line, Id kf, int index);
  /// Removes the point and every keyframe reference to it.
  void erase_point(Id point);
  void erase_line(Id line);
  /// The view of feature observation `o`; nullopt when its keyframe is gone or the index is
  /// out of range.
  std::optional<FeatureView> feature_view(const Observation& o) const;
  /// The `n` newest keyframe ids, oldest first.
  std::vector<Id> newest_keyframes(size_t n) const;
  void clear();
};

class Map {
 public:
  template <typename F>
  auto read(F&& f) const {
    std::lock_guard<std::mutex> lock(mutex_);
    return f(static_cast<const MapData&>(data_));
  }
  template <typename F>
  auto write(F&& f) {
    std::lock_guard<std::mutex> lock(mutex_);
    return f(data_);
  }

 private:
  mutable std::mutex mutex_;
  MapData data_;
};

}  // namespace pllvo::vo
