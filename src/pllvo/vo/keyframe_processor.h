#pragma once
// Everything done once per keyframe, on the worker thread: point detection, association with
// the map (KLT tracks, descriptor matches with the previous keyframe, and the recent keyframes'
// points found by projection), new 3-D points
// (stereo or two-view triangulation), and the sliding-window bundle adjustment.
#include <atomic>
#include <map>
#include <memory>
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "pllvo/vo/geometry_adapter.h"
#include "pllvo/vo/keyframe_matcher.h"
#include "pllvo/vo/line_mapper.h"
#include "pllvo/vo/map.h"
#include "pllvo/vo/point_frontend.h"
#include "pllvo/vo/point_tracker.h"
#include "pllvo/vo/projection_search.h"
#include "pllvo/vo/run_stats.h"
#include "pllvo/vo/vo_config.h"

namespace pllvo::vo {

/// A point followed into a frame: either of a map point, or a candidate (no map point yet)
/// remembered by its first keyframe observation, from which it will be triangulated.
struct TrackedPoint {
  cv::Point2f px;
  Id point = kNoId;
  Observation origin;  ///< candidates: keyframe and feature where the track began
  Observation last;    ///< the latest keyframe observation of the track
  /// Candidates, live input only (pose.provisional_points): world position triangulated by the
  /// tracker from the track's keyframe views and its latest tracked frame; not in the map.
  std::optional<Eigen::Vector3d> provisional = std::nullopt;
};

struct KeyframeJob {
  size_t frame_index = 0;
  double timestamp = 0;
  cv::Mat left, right;         ///< working images (right empty for mono and RGB-D)
  cv::Mat depth;               ///< RGB-D: `left`'s depth, CV_32F metres (0: none); else empty
  ImagePyramid left_pyramid;   ///< built by the tracker for this frame
  geometry::Pose T_world_cam = geometry::Pose::Identity();
  KeyframeReason reason = KeyframeReason::kNone;
  double image_noise = 0;            ///< the frame's pixel noise, grey levels (estimate_noise_sigma)
  std::vector<TrackedPoint> tracks;  ///< KLT tracks in this frame (map points and candidates)
  std::vector<TrackedLine> lines;    ///< lines tracked into this frame
  /// Segments parallel to known directions, at the frame's pose (directions.*); empty: none.
  std::vector<backend::PoseDirectionObservation> directions;
  /// EDLines detections of `left` the tracker made already (directions.*), before the cross
  /// constraint; absent: the keyframe detects its lines itself.
  std::optional<std::vector<lines::LineSegment>> line_detections;
  bool first = false;                ///< first keyframe of a map segment (stereo initialisation)
};

struct KeyframeResult {
  bool ok = false;
  Id keyframe = kNoId;
  size_t frame_index = 0;
  std::vector<TrackedPoint> tracks;  ///< the keyframe's points: map points and candidates
  std::vector<TrackedLine> lines;    ///< the keyframe's lines: map lines and candidates
  /// Filled by the odometry before the result reaches the tracker: the keyframe's points and
  /// lines that the tracker does not follow yet, positioned in frame `followed_frame`.
  std::vector<TrackedPoint> new_tracks;
  std::vector<TrackedLine> new_lines;
  size_t followed_frame = 0;
  geometry::Pose T_world_cam = geometry::Pose::Identity();  ///< the keyframe's pose as added
  geometry::Pose T_world_cam_adjusted = geometry::Pose::Identity();  ///< ...and after its bundle adjustment
  bool relocalised = false;          ///< a first keyframe placed by relocalisation (pose.relocalise_min_inliers)
  int matches = 0;                   ///< features linked to the previous keyframe (KLT tracks + matcher)
  int new_points = 0;
  int created_lines = 0;
  double stereo_offset_px = 0;  ///< the stereo pair's offset after this keyframe's window BA
};

struct DetectedKeyframe {
  PointFeatures features;
  double detect_ms = 0;  ///< counted in the keyframe's total time (kf_total)
  /// Set by KeyframeProcessor::relocalise_in_segment: a restart's first keyframe takes this
  /// pose instead of matching the same keyframes a second time.
  std::optional<geometry::Pose> relocalised_T_world_cam;
};

class KeyframeProcessor {
 public:
  /// `baseline` > 0: a metric map, from a stereo pair or, with `depth_images`, from the jobs'
  /// depth (VoConfig::depth: `baseline` is then the virtual pair's).
  KeyframeProcessor(const VoConfig& config, const Pinhole& camera, double baseline, Map& map, RunStats& stats,
                    bool depth_images = false);

  /// Runs on the worker (or inline in single-thread mode). A first keyframe that yields
  /// too few 3-D points is not added (result.ok false).
  KeyframeResult process(const KeyframeJob& job) { return process(job, detect_keyframe(job)); }
  /// The first part of process(): the keyframe's point features (its tracked points described
  /// where they are, then new detections). It reads nothing of the map, so it may run on a
  /// thread of its own while the previous keyframe's second part runs.
  DetectedKeyframe detect_keyframe(const KeyframeJob& job);
  /// The second part: everything after detection, given detect_keyframe(job).
  KeyframeResult process(const KeyframeJob& job, DetectedKeyframe detected);

  /// Monocular initialisation: adds the reference keyframe (already detected features,
  /// a triangulated point or nullopt per feature) and then processes `second` as a keyframe;
  /// `second_px[i]` is reference feature i followed into the second frame (NaN when lost).
  KeyframeResult initialize_mono(const KeyframeJob& reference, const PointFeatures& ref_features,
                                 const std::vector<std::optional<Eigen::Vector3d>>& ref_points_world,
                                 KeyframeJob second, const std::vector<cv::Point2f>& second_px);

  /// Detection for the tracker's own use (monocular initialisation); not thread-safe with process().
  PointFeatures detect(const cv::Mat& image);

  /// The next keyframe starts a new map segment (after a tracking loss); the last keyframes of
  /// the segment that ends are where a restart relocalises.
  void start_segment();
  /// Whether the segment before the latest loss can still resume (resume_segment).
  bool can_resume() const { return !previous_segment_keyframes_.empty() && segment_keyframes_.empty(); }
  /// Monocular restart (pose.mono_resume_max_s): when this frame's `features` relocalise
  /// against the last keyframes before the loss, the segment before the loss resumes with this
  /// frame as its next keyframe, so the map keeps its scale. result.ok is false otherwise.
  KeyframeResult resume_segment(KeyframeJob job, PointFeatures features);
  /// Whether this frame's features relocalise against the last keyframes of the current
  /// segment (pose.relocalise_*), i.e. whether a stereo restart on it would be placed in this
  /// map; the pose is kept in `detected` for that restart. Not thread-safe with process().
  bool relocalise_in_segment(const KeyframeJob& job, DetectedKeyframe& detected);
  int segment() const { return segment_; }
  const std::string& frontend_name() const { return frontend_name_; }
  std::string matcher_name() const { return matcher_->name(); }

 private:
  /// frontend.min_corner_ratio: drops the new detections (not the tracked points) whose KLT
  /// window is a plain edge.
  PointFeatures drop_edge_points(const cv::Mat& image, PointFeatures features);
  geometry::Pose current_pose(const KeyframeJob& job);
  /// The pose of a segment's first keyframe against the last keyframes before the loss
  /// (pose.relocalise_keyframes), when enough of its matches' map points agree
  /// (pose.relocalise_min_inliers).
  std::optional<geometry::Pose> relocalise(const KeyframeJob& job, const PointFeatures& features) {
    return relocalise(job, features, previous_segment_keyframes_);
  }
  /// The same against `keyframes` (oldest first).
  std::optional<geometry::Pose> relocalise(const KeyframeJob& job, const PointFeatures& features,
                                           const std::vector<Id>& keyframes);
  /// The first keyframe of a stereo segment: enough metric points and lines to start on.
  bool stereo_start_ok(const std::vector<std::optional<Eigen::Vector3d>>& stereo, int stereo_lines) const;
  /// New points from the stereo pair for features without a map point; `right_px` gets the
  /// right-image position of every feature with a valid stereo match (NaN elsewhere).
  std::vector<std::optional<Eigen::Vector3d>> stereo_points(const KeyframeJob& job, const PointFeatures& features,
                                                            const std::vector<Id>& ids,
                                                            std::vector<cv::Point2f>& right_px);
  /// The same from the job's depth image (RGB-D, VoConfig::depth): the virtual right-image
  /// position u - f b / d of every feature with a valid depth.
  std::vector<std::optional<Eigen::Vector3d>> depth_points(const KeyframeJob& job, const PointFeatures& features,
                                                           const std::vector<Id>& ids,
                                                           std::vector<cv::Point2f>& right_px);
  /// Matches of the new keyframe's `features` with the previous keyframe's. With
  /// mapping.match_untracked_only, the features KLT already links to it are left out of the
  /// matcher and `linked` gets their count; otherwise every feature is matched and `linked` is 0.
  std::vector<PointMatch> match_previous(const Keyframe& prev, const KeyframeJob& job, const PointFeatures& features,
                                         int& linked);
  /// Features without a point that match a recent keyframe's point by projection get it
  /// (mapping.projection_search); they stop being candidates.
  void reattach_by_projection(const geometry::Pose& T_world_cam, const PointFeatures& features, std::vector<Id>& ids,
                              std::vector<Observation>& origins, std::vector<Observation>& previous);

  /// mapping.mono_align_to_origin: each candidate feature moves onto its patch in its origin
  /// keyframe (PointTracker::align); one that does not align loses its link and starts again here.
  void align_to_origins(const KeyframeJob& job, PointFeatures& features, const std::vector<Id>& ids,
                        std::vector<Observation>& origins, std::vector<Observation>& previous);
  /// Keeps a monocular keyframe's tracking image for align_to_origins (the newest ones only).
  void remember_image(Id keyframe, const KeyframeJob& job);
  /// Two-view angle for this keyframe's new 3-D lines (`features` point detections):
  /// plain_scene.mono_line_min_plane_angle_deg on plain, quiet monocular keyframes, else none
  /// (the triangulation config's).
  std::optional<double> line_plane_angle(const KeyframeJob& job, size_t features) const;
  /// The window BA's settings for a keyframe with this image noise (the monocular gauge).
  backend::BundleAdjustmentConfig window_ba_config() const;

  VoConfig config_;
  Pinhole camera_;
  double baseline_;
  bool depth_images_;  ///< RGB-D: the jobs' depth in place of a right image
  /// The rectified stereo pair's horizontal offset (pixels: true disparity = measured + this),
  /// as the last window BA estimated it; new stereo points are triangulated with it.
  double stereo_offset_px_ = 0;
  Map& map_;
  RunStats& stats_;
  std::unique_ptr<PointFrontend> frontend_;
  std::unique_ptr<KeyframeMatcher> matcher_;
  std::string frontend_name_;
  PointTracker klt_;  ///< the keyframe's own LK: stereo matching and origin alignment
  std::unique_ptr<LineMapper> line_mapper_;  ///< null when lines are off
  /// Read by the tracking thread every frame while a monocular resume on the worker may set it.
  std::atomic<int> segment_ = 0;
  int last_segment_ = 0;               ///< the highest segment number given out (a resumed one reuses its own)
  std::vector<Id> segment_keyframes_;  ///< keyframes of the current segment, oldest first
  int previous_segment_ = 0;           ///< the segment before the latest loss...
  std::vector<Id> previous_segment_keyframes_;  ///< ...and its keyframes (oldest first), until it resumes
  /// Newest mono keyframes' images as PointTracker::reference_levels (mono_align_to_origin).
  std::map<Id, std::vector<cv::Mat>> keyframe_images_;
};

}  // namespace pllvo::vo
