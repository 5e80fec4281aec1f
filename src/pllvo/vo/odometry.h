#pragma once
// The visual odometry: per-frame tracking on the caller's thread (KLT of the keyframe's
// points, PnP + RANSAC, robust refinement, keyframe decision), keyframe processing on a
// worker thread (or inline in single-thread mode), re-initialisation after a loss.
#include <chrono>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <vector>

#include "pllvo/features/lines/line_detector.h"
#include "pllvo/features/lines/line_tracker.h"
#include "pllvo/features/lines/overlap_angles.h"
#include "pllvo/io/sequence.h"
#include "pllvo/vo/direction_map.h"
#include "pllvo/vo/frame_rectifier.h"
#include "pllvo/vo/frame_corners.h"
#include "pllvo/vo/keyframe_policy.h"
#include "pllvo/vo/keyframe_processor.h"
#include "pllvo/vo/keyframe_worker.h"
#include "pllvo/vo/map.h"
#include "pllvo/vo/point_tracker.h"
#include "pllvo/vo/run_output.h"
#include "pllvo/vo/run_stats.h"
#include "pllvo/vo/vo_config.h"

namespace pllvo::vo {

enum class TrackingState { kUninitialized, kTracking };

/// What a start step on the keyframe worker hands back to the tracker.
struct StartOutcome {
  size_t frame_index = 0;
  double timestamp = 0;
  cv::Mat image;          ///< the frame's working image
  KeyframeResult result;  ///< ok: the map resumed or started; its tracks in new_tracks at followed_frame
  PointFeatures features; ///< a detection that did not resume: a new reference's features
  /// The features followed into the frames after frame_index (NaN: lost), oldest first.
  std::vector<std::pair<size_t, std::vector<cv::Point2f>>> followed;
  /// A map that started: the poses of the frames after frame_index that it was followed into.
  std::vector<std::pair<size_t, geometry::Pose>> poses;
};

/// What the tracker holds after a frame: its working image (rectified / undistorted left) and
/// the points and lines it follows there. For viewers and report frames; a copy of references.
struct TrackingView {
  size_t frame_index = 0;
  bool tracked = false;
  cv::Mat image;
  std::vector<TrackedPoint> points;  ///< point != kNoId: a map point; else a candidate
  std::vector<TrackedLine> lines;    ///< line != kNoId: a map line; else a candidate
};

class Odometry {
 public:
  /// `use_stereo`: use cam1 when the calibration has one; else `use_depth`: use cam0's depth
  /// images when the calibration has them (RGB-D, VoConfig::depth); else monocular.
  Odometry(const VoConfig& config, const io::Calibration& calibration, bool use_stereo, bool use_depth,
           RunStats& stats);
  ~Odometry();

  /// Processes one frame; never throws on image content (dark, blank, textureless frames
  /// just are not tracked). InputError for a frame whose size differs from the calibration.
  FrameRecord process(const io::Frame& frame);
  /// Waits for pending keyframe jobs and applies a start still on its way (call before reading
  /// the final map).
  void finish();

  const std::vector<FrameRecord>& records() const { return records_; }
  TrackingState state() const { return state_; }
  bool stereo() const { return rectifier_.stereo(); }
  bool depth() const { return rectifier_.depth(); }  ///< RGB-D
  /// Stereo or RGB-D: every keyframe measures depth, a map starts on one frame at metric scale.
  bool metric() const { return stereo() || depth(); }
  /// The keyframe matcher actually used (after the LightGlue -> MNN fallback).
  std::string matcher_name() const { return processor_.matcher_name(); }
  /// The point front end actually used (frontend.type auto resolved).
  const std::string& frontend_name() const { return processor_.frontend_name(); }
  int resets() const { return resets_; }
  /// Keyframe poses (T_world_cam0, after bundle adjustment) with their timestamps.
  io::Trajectory keyframe_trajectory() const;
  /// The map's keyframes with their current poses (output camera) and frames.
  std::vector<KeyframePose> keyframe_poses() const;
  /// Map in the output world frame.
  MapData map_snapshot() const;
  const RunStats& stats() const { return stats_; }
  /// The latest processed frame as the tracker sees it.
  TrackingView tracking_view() const;

 private:
  struct MonoReference {
    size_t frame_index = 0;
    double timestamp = 0;
    cv::Mat image;
    PointFeatures features;
    std::vector<cv::Point2f> current;   ///< each feature followed into the latest frame
    std::vector<unsigned char> alive;   ///< still tracked
    size_t frames = 0;
    /// Frames between the reference and now with each feature's position (NaN: lost), so
    /// that they get a pose once the map exists.
    std::vector<std::pair<size_t, std::vector<cv::Point2f>>> history;
    std::vector<Eigen::Vector3d> directions;  ///< of its image alone (geometry.two_view.vanishing_sigma_deg)
  };

  /// A new map on this frame. Stereo: `detected` holds its features when already detected, and
  /// `relocalised` (if given) tells whether the map was placed in the one before the loss.
  bool initialize(const io::Frame& frame, const cv::Mat& left, const cv::Mat& right, const ImagePyramid& pyramid,
                  std::optional<DetectedKeyframe> detected = std::nullopt, bool* relocalised = nullptr);
  /// A keyframe job for this frame at the current pose (tracks and lines not filled in).
  KeyframeJob make_keyframe_job(const io::Frame& frame, const cv::Mat& left, const cv::Mat& right,
                                const ImagePyramid& pyramid, KeyframeReason reason) const;
  bool initialize_stereo(const io::Frame& frame, const cv::Mat& left, const cv::Mat& right,
                         const ImagePyramid& pyramid, std::optional<DetectedKeyframe> detected, bool* relocalised);
  bool initialize_mono(const io::Frame& frame, const cv::Mat& left, const ImagePyramid& pyramid);
  /// The directions this image shows alone, for a monocular start (empty when not used).
  std::vector<Eigen::Vector3d> start_directions(const cv::Mat& image, size_t frame_index);
  /// pose.mono_resume_max_s: whether this frame may try to resume the map before the loss.
  bool may_resume(const io::Frame& frame) const;
  /// On the worker: this frame's point detection, which resumes the map before the loss when
  /// `resume` and it relocalises there, and otherwise may open a new monocular reference.
  void submit_start_detection(const io::Frame& frame, const cv::Mat& left, const ImagePyramid& pyramid, bool resume);
  /// On the worker: a stereo or RGB-D map's first keyframe.
  void submit_metric_start(const KeyframeJob& job);
  /// On the worker: the two keyframes of a two-view start (MonoStart holds the rest).
  void submit_two_view_start(const KeyframeJob& reference, const PointFeatures& features,
                             const std::vector<std::optional<Eigen::Vector3d>>& points, const KeyframeJob& second,
                             const std::vector<cv::Point2f>& second_px);
  /// On the worker: a map that started at `job`'s frame, followed through the frames that
  /// passed meanwhile (StartOutcome::poses), as prepare_result does for a keyframe.
  void catch_up_on_worker(const KeyframeJob& job, StartOutcome& outcome) const;
  /// Runs `step` as the one start step in flight; offline input (run.wait_when_starving) waits
  /// for it, so that its outcome applies to this frame as it would on one thread.
  void submit_start(size_t frame_index, std::function<StartOutcome()> step);
  /// Applies a start step that came back: the map it resumed or started (brought up to the
  /// latest frame), or the reference its detection opens. True when the map starts at
  /// `current` itself, which then counts as tracked; `relocalised` then tells whether it
  /// started in the map before a loss.
  bool apply_start_outcome(size_t current, bool* relocalised = nullptr);
  /// A new monocular reference from a detection; `late`: its features are followed from the
  /// last frame the worker reached up to the latest processed one.
  void open_reference(StartOutcome& outcome, bool late);
  /// Follows `positions` (NaN: lost) through `frames` (consecutive, from the frame they are in),
  /// appending each later frame's positions to `history`. Safe on the worker thread.
  void follow_positions(const std::vector<std::pair<size_t, ImagePyramid>>& frames, std::vector<cv::Point2f>& positions,
                        std::vector<std::pair<size_t, std::vector<cv::Point2f>>>& history) const;
  /// The buffered pyramids from frame `first` to the latest processed frame (empty when the
  /// buffer does not reach back to `first`).
  std::vector<std::pair<size_t, ImagePyramid>> buffered_since(size_t first) const;
  /// Frame `frame_index`'s `pyramid` and the buffered ones of the frames after it.
  std::vector<std::pair<size_t, ImagePyramid>> frames_from(size_t frame_index, const ImagePyramid& pyramid) const;
  using FollowStep = std::function<void(const std::vector<std::pair<size_t, ImagePyramid>>&)>;
  /// On the worker, what a keyframe's or a start's new tracks are followed through: `step`
  /// through `job`'s frame and the buffered ones after it, then through the frames the tracker
  /// finished meanwhile, up to run.worker_catch_up_rounds times. Returns the last frame followed.
  size_t follow_to_newest(const KeyframeJob& job, const FollowStep& step) const;
  /// track(); when the pose fails, handle_lost() and (stereo, pose.stereo_restart_at_once) a
  /// new map on this frame when it relocalises in the old one; it then counts as tracked.
  bool track_or_restart(const io::Frame& frame, const cv::Mat& left, const cv::Mat& right,
                        const ImagePyramid& pyramid, FrameRecord& record);
  bool track(const io::Frame& frame, const cv::Mat& left, const cv::Mat& right, const ImagePyramid& pyramid,
             FrameRecord& record);
  /// Monocular frame whose pose failed on the map: the motion from the previous frame by the
  /// essential matrix of every track that KLT followed (`from` -> tr.points), scaled by the last
  /// velocity (pose.mono_frame_motion_*). point_inliers are given per entry of `map_tracks`.
  PoseEstimate pose_from_frame_motion(size_t frame_index, const std::vector<cv::Point2f>& from,
                                      const TrackResult& tr, const std::vector<size_t>& map_tracks,
                                      size_t num_lines) const;
  void maybe_make_keyframe(const io::Frame& frame, const cv::Mat& left, const cv::Mat& right,
                           const ImagePyramid& pyramid, int tracked_points);
  void submit_keyframe(KeyframeJob job);
  void apply_keyframe_results();
  /// Follows points and lines through `frames` (consecutive, starting with the frame they are
  /// in); drops what gets lost. Safe on the worker thread.
  void follow(const std::vector<std::pair<size_t, ImagePyramid>>& frames, std::vector<TrackedPoint>& points,
              std::vector<TrackedLine>& lines) const;
  /// On the worker: splits a finished keyframe's points and lines into those the tracker
  /// already follows (same identity as in `job`) and new ones, and brings the new ones up to
  /// the newest buffered frame.
  void prepare_result(const KeyframeJob& job, KeyframeResult& result) const;
  /// Drops merged tracks whose map point does not project near the track at the latest pose
  /// (pose.merge_gate_px); first, under pose.follow_keyframe_adjustment, that pose may move by
  /// `result`'s bundle-adjustment correction.
  void drop_inconsistent_tracks(std::vector<TrackedPoint>& tracks, const KeyframeResult& result);
  void drop_inconsistent_lines(std::vector<TrackedLine>& lines) const;
  /// Tracking from a new or resumed map (its keyframe's tracks and lines) from `timestamp` on.
  void start_tracking(const KeyframeResult& result, double timestamp);
  /// Poses of the frames seen during monocular initialisation, by PnP on the new map.
  void localize_init_frames(const MonoReference& ref, const std::vector<std::optional<Eigen::Vector3d>>& points,
                            const geometry::Pose& T_world_ref);
  /// The record of an earlier frame (nullptr: not among them, as the current frame is not yet).
  FrameRecord* record_of(size_t frame_index);
  /// A start's tracks (in the first of `frames`, consecutive) followed through the others, with
  /// each later frame's pose by PnP on the map appended to `poses` where it is found. Safe on
  /// the worker thread.
  void follow_and_locate(const std::vector<std::pair<size_t, ImagePyramid>>& frames, std::vector<TrackedPoint>& points,
                         std::vector<TrackedLine>& lines,
                         std::vector<std::pair<size_t, geometry::Pose>>& poses) const;
  /// Follows `lines` from one pyramid to the next; drops those the tracker rejects. `plain`:
  /// a plain scene's frame (plain_scene.max_tracked_points), tracked with aperture handling.
  /// Re-detection mode (pipeline.line_tracking: redetect): `detected` holds the detector's
  /// segments of `to` (before the cross constraint); without them no line is kept.
  std::vector<TrackedLine> track_lines(const ImagePyramid& from, const ImagePyramid& to,
                                       const std::vector<TrackedLine>& lines, bool plain,
                                       const std::vector<lines::LineSegment>* predicted = nullptr,
                                       const std::vector<lines::LineSegment>* detected = nullptr) const;
  /// pose.provisional_points on, and live input (offline waits for the keyframe instead).
  bool makes_provisional_points() const { return config_.pose.provisional_points && !config_.run.wait_when_starving; }
  /// makes_provisional_points(), and the frame follows fewer map points than
  /// run.starving_points: its candidates' provisional positions join the pose.
  bool uses_provisional_points() const;
  /// KLT's starting point for a track at `px`: where `position` (none: unknown) projects at
  /// `T_pred_world`, unless the map is held (holding_map: its last pose is frames old).
  cv::Point2f klt_seed(const Eigen::Vector3d* position, const cv::Point2f& px,
                       const geometry::Pose& T_pred_world) const;
  /// Gives every candidate track its provisional position from its keyframe views and the
  /// latest pose (nullopt where the triangulation's checks fail).
  void triangulate_candidates();
  /// Follows the tracker's own corners (pose.frame_corners) into `pyramid`, predicted at
  /// `T_pred_world` where they have a position; those KLT loses are dropped.
  void follow_corners(const ImagePyramid& pyramid, const geometry::Pose& T_pred_world);
  /// After a tracked frame: monocular, every corner triangulated from its first view and this
  /// pose; and, when the frame follows fewer than run.starving_points map points, new corners
  /// found in `pyramid`'s image (metric maps: only those with a stereo or depth measurement here).
  void refresh_corners(const ImagePyramid& pyramid, const cv::Mat& right, int map_inliers);
  /// Metric maps: each of `found` in this frame's right image or depth, in the world at this
  /// frame's pose (nullopt where it has none).
  std::vector<std::optional<Eigen::Vector3d>> measure_corner_depths(const ImagePyramid& pyramid, const cv::Mat& right,
                                                                    const std::vector<cv::Point2f>& found);
  bool uses_frame_corners() const;
  /// Whether this frame follows fewer map points than plain_scene.max_tracked_points.
  bool plain_frame() const;
  void set_reference_lines(const std::vector<TrackedLine>& lines);
  std::optional<double> line_angle_distance() const;
  /// Counts a failed frame at `timestamp`; resets after pose.lost_frames_before_reset, unless
  /// the map is held for a keyframe in flight (pose.hold_map_for_keyframe_s).
  void handle_lost(double timestamp);
  /// Whether the map is held past pose.lost_frames_before_reset for a keyframe in flight.
  bool holding_map() const { return lost_frames_ >= config_.pose.lost_frames_before_reset; }
  /// Whether a frame that just failed stays out of the KLT reference (pose.keep_reference_over_failed_frames):
  /// the map still waits for its pose and is not held.
  bool keeps_reference_over_failure() const {
    return config_.pose.keep_reference_over_failed_frames && state_ == TrackingState::kTracking && lost_frames_ > 0 &&
           !holding_map();
  }
  void reset();
  /// Where a map started at `frame_index` (time `timestamp`) after a reset begins, unless it
  /// relocalises: the last tracked pose, its position carried on by the mean step of the frames
  /// before it (pose.extrapolate_velocity_frames) within pose.extrapolate_gap_max_s.
  geometry::Pose restart_pose(size_t frame_index, double timestamp) const;
  /// Keeps the positions of the last consecutive tracked frames for restart_pose.
  void remember_position(size_t frame_index, const Eigen::Vector3d& position);
  geometry::Pose to_output(const geometry::Pose& T_world_work) const;
  /// Smooths both images when the left one's noise reaches klt.denoise_min_noise (low light);
  /// returns that noise (grey levels), which also sets the frame's run.starving_points_at.
  double denoise(cv::Mat& left, cv::Mat& right);
  /// Scales both images by one gain so that the left image's mean is klt.normalize_mean.
  void normalize_brightness(cv::Mat& left, cv::Mat& right) const;

  /// The detector's segments of the frame's image (`frame_index`), detected once a frame:
  /// line re-detection, the directions and the frame's keyframe share them.
  const std::vector<lines::LineSegment>& frame_lines(const cv::Mat& image, size_t frame_index);
  /// The lines detected in the frame (`frame_index`) as direction segments (normalised,
  /// working camera).
  std::vector<DirectionSegment> direction_segments(const cv::Mat& image, size_t frame_index);
  /// The segments on known directions at rotation R_cam_world (none while fewer than
  /// directions.min_known are known).
  std::vector<backend::PoseDirectionObservation> direction_observations(const std::vector<DirectionSegment>& segments,
                                                                        const Eigen::Matrix3d& R_cam_world) const;

  VoConfig config_;
  RunStats& stats_;
  FrameRectifier rectifier_;
  Pinhole camera_;
  PointTracker tracker_;
  bool use_lines_;
  bool redetect_lines_;  ///< pipeline.line_tracking: redetect
  lines::LineTracker line_tracker_;
  lines::LineTracker plain_line_tracker_;  ///< the same with aperture handling (plain_scene)
  lines::LineDetector line_detector_;  ///< tracking thread: redetect mode, directions
  bool use_directions_;                ///< directions.mono / directions.stereo (needs lines)
  DirectionMap directions_;            ///< world directions of the tracked lines (tracking thread)
  /// The last tracked frame's segments on known directions, at its pose (for its keyframe).
  std::vector<backend::PoseDirectionObservation> frame_directions_;
  /// The frame whose lines frame_lines() detected last, and those detections: a keyframe of
  /// that frame hands them to the worker, which would otherwise detect them again.
  size_t detected_lines_frame_ = 0;
  std::optional<std::vector<lines::LineSegment>> detected_lines_;
  KeyframePolicy policy_;
  Map map_;
  KeyframeProcessor processor_;
  KeyframeWorker worker_;

  TrackingState state_ = TrackingState::kUninitialized;
  std::vector<TrackedPoint> tracks_;
  std::vector<TrackedLine> line_tracks_;
  std::vector<FrameCorner> corners_;  ///< pose.frame_corners: live input only
  /// The stereo pair's offset as the latest keyframe's window BA left it (KeyframeResult).
  double stereo_offset_px_ = 0;
  lines::OverlapAngleSet reference_angles_;  ///< of the current keyframe's lines
  /// The KLT reference: the latest frame, unless it failed (pose.keep_reference_over_failed_frames).
  ImagePyramid previous_pyramid_;
  cv::Mat previous_image_;  ///< working left image of the latest frame (tracking_view)
  size_t previous_index_ = 0;
  geometry::Pose T_world_work_;                 ///< latest tracked pose (working camera)
  geometry::Pose velocity_ = geometry::Pose::Identity();  ///< T_prev_cur of the last tracked step
  bool has_velocity_ = false;
  int lost_frames_ = 0;
  int frame_motion_run_ = 0;  ///< consecutive frames posed by pose_from_frame_motion
  /// The last tracked frame, and the mean position step per frame before it, kept over a reset
  /// (restart_pose), from the positions of the last consecutive tracked frames.
  size_t last_tracked_index_ = 0;
  double last_tracked_time_ = 0;
  std::deque<std::pair<size_t, Eigen::Vector3d>> recent_positions_;
  std::optional<Eigen::Vector3d> gap_step_world_;
  double frame_noise_ = 0;       ///< pixel noise of the current left image (estimate_noise_sigma)
  cv::Mat frame_depth_;          ///< RGB-D: the current frame's working depth (metres), else empty
  double frame_brightness_ = 0;  ///< mean grey level of the current left image before normalisation
  int resets_ = 0;
  geometry::Pose T_work_cam0_;
  std::unique_ptr<MonoReference> mono_;
  /// A two-view start whose keyframes are on the worker: what applies once they come back.
  struct MonoStart {
    std::vector<std::optional<Eigen::Vector3d>> points;  ///< per reference feature, world
    geometry::Pose T_world_ref, T_world_cur;
    std::string summary;  ///< for the log line
  };
  std::optional<MonoStart> two_view_start_;
  /// Starts and monocular resumes run their networks on the keyframe worker, one step at a
  /// time, so that a live tracker keeps taking frames meanwhile (they are buffered).
  bool start_in_flight_ = false;
  std::optional<StartOutcome> start_outcome_;  ///< written by the worker (results_mutex_)
  /// The latest detection that neither resumed nor opened a reference: a reference that fails
  /// on that same frame reopens on it instead of detecting again.
  std::optional<StartOutcome> spare_detection_;
  /// The reference has moved enough for a two-view start while a resume try was running: the
  /// next free step is the two-view start, not another try.
  bool two_view_waiting_ = false;

  // Keyframe results come back from the worker; tracks found on a keyframe are brought up
  // to date through the pyramids of the frames that passed meanwhile.
  std::mutex results_mutex_;
  std::deque<KeyframeResult> results_;
  std::set<size_t> pending_keyframe_frames_;
  /// When each pending keyframe was asked for: its return time and the frames that passed
  /// meanwhile are the keyframe's age when it reaches the tracker (stats: keyframe_return_*).
  std::map<size_t, std::chrono::steady_clock::time_point> keyframe_requested_at_;
  /// Pyramids of the frames since the oldest pending keyframe; the worker reads them to bring
  /// a finished keyframe's new points up to date before handing it back.
  class PyramidBuffer {
   public:
    void push(size_t frame_index, const ImagePyramid& pyramid, size_t capacity);
    /// Frames from `first` on, in order.
    std::vector<std::pair<size_t, ImagePyramid>> from(size_t first) const;
    void drop_before(size_t frame_index);
    void clear();

   private:
    mutable std::mutex mutex_;
    std::deque<std::pair<size_t, ImagePyramid>> frames_;
  };
  PyramidBuffer pyramid_buffer_;

  std::vector<FrameRecord> records_;
};

}  // namespace pllvo::vo
