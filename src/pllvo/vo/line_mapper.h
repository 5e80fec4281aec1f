#pragma once
// The lines of a keyframe (worker thread): EDLines detection with the cross constraint,
// identity from the lines tracked into the keyframe and from the previous keyframe
// (association through matched points, paper 3.3), and new 3-D lines by two-view
// triangulation. plan() reads the map; commit() writes the plan under the map's lock.
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "pllvo/features/lines/line_associator.h"
#include "pllvo/features/lines/line_detector.h"
#include "pllvo/features/lines/lines_config.h"
#include "pllvo/geometry/line3d.h"
#include "pllvo/geometry/line_triangulation.h"
#include "pllvo/vo/geometry_adapter.h"
#include "pllvo/vo/map.h"

namespace pllvo::vo {

/// A line followed into a frame by line optical flow: of a map line, or a candidate
/// remembered by its keyframe observations.
struct TrackedLine {
  lines::LineSegment segment;  ///< pixels
  Id line = kNoId;
  Observation origin;  ///< first keyframe observation (candidates)
  Observation last;    ///< latest keyframe observation
};

Segment2d to_segment2d(const lines::LineSegment& s);
lines::LineSegment to_line_segment(const Segment2d& s, int id = -1);

struct LinePlan {
  std::vector<lines::LineSegment> segments;  ///< detected in the keyframe (after the cross constraint)
  cv::Mat descriptors;                        ///< LBD rows (empty when descriptors are off)
  std::vector<Id> ids;                        ///< map line per segment, or kNoId
  std::vector<Observation> origins;           ///< candidates: first observation (kNoId: this keyframe)
  std::vector<Observation> previous;          ///< candidates: latest earlier observation, if newer than origin
  std::vector<std::optional<geometry::LineSegment3d>> triangulated;  ///< new map lines (world)
  int from_tracks = 0, from_association = 0;
  int from_stereo = 0;  ///< new map lines triangulated from the left-right pair
};

class LineMapper {
 public:
  LineMapper(const lines::LinesConfig& lines, const geometry::LineTriangulationConfig& triangulation,
             const Pinhole& camera);

  /// Detects the keyframe's lines and decides their identities and new 3-D lines.
  /// `previous` is the previous keyframe of the segment (null for the first one);
  /// `point_matches` pairs pixels of the same points in `previous` and this keyframe.
  /// With a rectified right image (`baseline` > 0), lines left without a 3-D line are matched
  /// left-right and triangulated at metric scale. `min_plane_angle_deg` replaces the
  /// triangulation config's angle for this keyframe's two-view lines. `detections`: the
  /// detector's segments of `image` when made already (the cross constraint still applies).
  LinePlan plan(const cv::Mat& image, const geometry::Pose& T_world_cam, const std::vector<TrackedLine>& tracked,
                const Keyframe* previous, const std::vector<lines::PointMatch>& point_matches, const Map& map,
                const cv::Mat& right = {}, double baseline = 0.0,
                std::optional<double> min_plane_angle_deg = std::nullopt,
                const std::vector<lines::LineSegment>* detections = nullptr);

  /// Stores the plan's lines in keyframe `kf` (already added with plan.segments as its lines).
  /// Returns the number of new map lines.
  static int commit(MapData& map, Id kf, const LinePlan& plan);

  /// Detection with the cross constraint (also for the monocular reference keyframe).
  std::vector<lines::LineSegment> detect(const cv::Mat& image);

 private:
  std::vector<lines::LineSegment> constrain(std::vector<lines::LineSegment> segments) const;
  void triangulate_stereo(const cv::Mat& image, const cv::Mat& right, double baseline,
                          const geometry::Pose& T_world_cam, LinePlan& plan);

  lines::LinesConfig config_;
  geometry::LineTriangulationConfig triangulation_;
  Pinhole camera_;
  lines::LineDetector detector_;
  lines::LineAssociator associator_;
};

}  // namespace pllvo::vo
