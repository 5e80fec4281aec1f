#pragma once
// Every threshold of the visual-odometry pipeline, with its default and the reason for it.
// A YAML file (config/vo.yaml) overrides only the keys it names; unknown keys are an error.
#include <algorithm>
#include <filesystem>
#include <string>

#include "pllvo/backend/backend_config.h"
#include "pllvo/common/yaml_config.h"
#include "pllvo/features/lines/lines_config.h"
#include "pllvo/geometry/geometry_config.h"

namespace pllvo::vo {

/// Point detection + description on keyframes (paper 3.1). One of three front ends.
struct FrontendConfig {
  std::string type = "auto";  ///< auto (superpoint if weights are found, else orb) | superpoint | orb | shitomasi
  /// Working view of a distorted camera (camera::WorkingView): "calibrated" keeps the calibration's
  /// focal lengths and image size, and EuRoC's barrel distortion then crops ~15 % of the raw
  /// width (a door frame at the side of a plain room); "fit" shrinks the focal lengths (EuRoC:
  /// 458 -> 356 / 418 px) so the same image spans the raw image from side to side; "whole" keeps
  /// them and enlarges the image (968 x 526), slower and, threaded, 4.7-5.1 % on stereo
  /// difficult_lowlight in two runs against 1.6-2.3 % with "fit" (docs/vo.md).
  std::string working_view = "fit";
  /// The same for monocular runs ("fit", one start over the suite: medium_lowlight 3.45 -> 1.02 %,
  /// but easy_flicker 0.85 -> 4.18 % and difficult_normal 1.07 -> 6.07 %; docs/vo.md).
  std::string mono_working_view = "calibrated";
  int max_points = 400;      ///< per keyframe; 300-500 keeps PnP well conditioned at low cost
  /// Detection is spread over a grid so points do not cluster on one textured patch.
  int grid_cols = 8;
  int grid_rows = 6;
  /// Minimum distance in pixels between a new point and one already tracked (masking).
  double min_distance_px = 12.0;
  // ORB (cv::ORB): pyramid and FAST threshold.
  int orb_levels = 4;
  double orb_scale_factor = 1.2;
  int orb_fast_threshold = 12;  ///< low, so that dim images still give corners
  // Shi-Tomasi (cv::goodFeaturesToTrack), described with ORB.
  double shitomasi_quality = 0.005;  ///< relative to the strongest corner; low for low light
  int shitomasi_block_size = 3;
  // SuperPoint (nn module): input scale chosen by measurement (see docs/vo.md).
  std::string superpoint_weights = "";  ///< file or folder; empty: the nn lookup ($PLLVO_MODELS, models/)
  double superpoint_input_scale = 0.5;
  double superpoint_threshold = 0.005;  ///< starting detection threshold
  bool superpoint_adaptive_threshold = true;
  int superpoint_nms_radius = 4;
  /// Convolution layout (nn::SuperPointConfig::conv_layout): nchw (the official numerics) |
  /// channels_last | mkldnn (oneDNN: detection 1.2x faster on an AVX2 host, docs/vo.md).
  std::string superpoint_conv_layout = "mkldnn";
  /// CLAHE before the network. Off: on dark frames the stretched sensor noise becomes
  /// SuperPoint keypoints (medium_lowlight: ATE 11.5 % of the path with it, 2.6 % without;
  /// docs/vo.md). The classical detectors use `equalize`.
  bool superpoint_equalize = false;
  /// Contrast stretching (CLAHE) before ORB / Shi-Tomasi detection helps in low light;
  /// tracking uses raw images.
  bool equalize = true;
  /// New points whose KLT window (klt.window_px) has a structure tensor with smaller / larger
  /// eigenvalue below this are dropped: a point on a plain straight edge slides along it from
  /// frame to frame (the aperture problem), and on plain walls the detector keeps such points
  /// (on medium_lowtexture, door-edge points moved 3-19 px against their
  /// projection; threaded stereo difficult_lowlight over starts 0-3 2.12 -> 1.58 % ATE,
  /// medium_lowtexture 5.22 -> 0.57 %). 0: off.
  double min_corner_ratio = 0.1;
  /// The same for monocular runs (for_mode): off, as fewer points cost the monocular start and
  /// scale (medium_lowtexture starts at frame 159, easy_normal 0.74 -> 1.79 %).
  double mono_min_corner_ratio = 0.0;
};

/// Pyramidal Lucas-Kanade tracking of keyframe points, frame to frame.
struct KltConfig {
  int window_px = 21;  ///< square window side
  int levels = 3;      ///< pyramid levels above the base (so 4 images)
  int max_iterations = 30;
  double epsilon = 0.01;
  /// Forward-backward check: a point tracked forward then backward must land within this
  /// distance of where it started; larger errors mean occlusion or drift.
  double fb_threshold_px = 1.0;
  /// Appearance check: the patches at both ends of a track must correlate (NCC) at least
  /// this much. The FB check alone accepts a wrong track when both directions fall into
  /// the same local minimum (occlusion by similar texture). -1 switches it off.
  double min_ncc = 0.75;
  double min_eigen_threshold = 1e-4;  ///< cv::calcOpticalFlowPyrLK's minEigThreshold
  double border_px = 4.0;             ///< points closer to the image edge are dropped
  /// Every frame (both cameras) is scaled by one gain so that its mean grey level is this:
  /// flicker and exposure changes then keep LK's brightness constancy. 0: off.
  double normalize_mean = 110.0;
  double max_normalize_gain = 6.0;  ///< the gain stays within [1/max, max]
  /// When fewer than this share of the points followed from one frame to the next survive (the
  /// map's tracks, the tracker's corners, a keyframe's points caught up over the frames since,
  /// a monocular start's points), they are tracked again on
  /// locally contrast-normalised images (zero mean, unit contrast over `contrast_window_px`):
  /// a sudden exposure change with clipped highlights, or uneven flicker, breaks the one-gain
  /// normalisation above, not this. Only a fallback: on ordinary frames it tracks worse
  /// (it amplifies noise and blur in flat areas). 0: off.
  double contrast_fallback_share = 0.3;
  int contrast_window_px = 15;
  /// Sensor noise: when the noise of a frame after the gain above (standard deviation in grey
  /// levels, estimated from the image itself) reaches `denoise_min_noise`, both images are
  /// smoothed with a Gaussian of `denoise_sigma_px` before tracking and detection. In low light
  /// the gain multiplies the shot and read noise (on the undistorted working images: 4-8 on the
  /// suite's low-light sequences, <= 2.5 on all others; 11-16 on the raw frames) and the NCC check
  /// then rejects most correct tracks: on difficult_lowlight frames, 13-38 of 300 corners survive
  /// FB + NCC raw, 63-87 after a 1.5 px blur (docs/vo.md). 0: off.
  double denoise_min_noise = 6.0;
  double denoise_sigma_px = 1.5;
  /// Stereo matches (rectified pairs) are finished by a 1-D search along the row
  /// (vo/stereo_row_match.h), dropping those whose window has less than this share of
  /// horizontal gradient energy: points on near-horizontal edges, whose disparity 2-D LK gets
  /// wrong by pixels. 0: the 2-D match as it is.
  double stereo_min_horizontal_share = 0.03;
};

/// Keyframe decision (paper 3.3). Every strategy can be switched off for ablations.
struct KeyframePolicyConfig {
  // (1) points: too few tracked, or the share of the keyframe's points still tracked falls.
  bool use_point_trigger = true;
  /// Also while a keyframe is in flight (made, its result not yet with the tracker). Off:
  /// the points it brings are awaited (run.starving_points guards tracking meanwhile);
  /// threaded, a drop below min_tracked_points otherwise made two keyframes a frame apart.
  bool point_trigger_while_in_flight = false;
  int min_tracked_points = 60;
  double min_tracked_ratio = 0.5;  ///< tracked now / tracked right after the keyframe
  // (2) time: a keyframe at least every max_interval_s; when the back end is idle, already
  // after min_interval_s (it has time to spare, and fresh keyframes keep the map dense).
  bool use_time_trigger = true;
  double max_interval_s = 1.0;
  double min_interval_s = 0.25;
  // (3) lines: distance (degrees, earth mover's) between the frame's set of line overlap
  // angles and the keyframe's; the view's structure changed when it grows.
  bool use_line_trigger = true;
  double line_angle_distance_deg = 8.0;
  /// Only while the back end is idle, like the min_interval_s rule: tracking is fine when it
  /// fires, so it must not queue work behind a busy worker. Threaded easy_normal: 28 of 70
  /// keyframes came from it, and without it the run was 1.2-1.4x faster (docs/vo.md).
  bool line_trigger_when_idle = true;
  int line_min_angles = 4;  ///< sets with fewer angles say nothing about the view
};

/// Initialisation: monocular two-view (E vs H) or stereo from rectified left-right matches.
/// The geometric thresholds (parallax, depths, epipolar error) are geometry.two_view and
/// geometry.stereo.
struct InitConfig {
  /// Features to open a monocular reference, points it must keep following, points the start
  /// must triangulate. 35, not 50: in a sparse room (medium_lowtexture, 36-49 features a frame)
  /// 50 dropped every reference before it had parallax, so the start came at frame 161 (78 now);
  /// the other eleven sequences start where they did (docs/vo.md).
  int min_points = 35;
  double mono_min_flow_px = 20.0; ///< median image motion before a two-view attempt
  int max_frames = 60;            ///< give up on a reference frame after this many frames
  /// Stereo points plus stereo lines needed for the first keyframe (of which at least
  /// pose.stereo_pnp_min_inliers points: PnP seeds the next frames' poses). With 30,
  /// medium_lowtexture started at frame 41-49.
  int stereo_min_points = 12;
  /// No map is started on a frame darker than this mean grey level: there, what the
  /// contrast-stretched detector finds is mostly sensor noise.
  double min_brightness = 10.0;
};

/// Per-frame pose: PnP + RANSAC (geometry.pnp), then the robust refinement with point and
/// line residuals and the motion prior (backend.pose_refiner).
struct PoseConfig {
  bool use_lines = true;          ///< line residuals in the refinement
  bool use_motion_prior = true;   ///< predict with the last velocity (constant velocity)
  /// Consecutive failures before re-initialising (stereo: see stereo_restart_at_once).
  int lost_frames_before_reset = 3;
  /// Stereo: a frame whose pose fails, and whose features relocalise against the map's last
  /// keyframes (pose.relocalise_*), starts the new map on itself at once, placed in the old
  /// one; it counts as tracked, with the relocalised pose. Otherwise the frame coasts on the
  /// tracks left (lost_frames_before_reset), which sometimes gets the pose back in the same map.
  /// On easy_flicker a flicker step lost frames 154-156 in 2 of 10 threaded runs, and frame 157
  /// relocalised at once (docs/vo.md). Counted in stats.json as
  /// `restarts_relocalised_at_once`. Offline input only: live, the try held the tracking thread
  /// 200-500 ms (stereo difficult_lowlight dropped 14-25 of 201 frames after its losses).
  bool stereo_restart_at_once = true;
  /// A frame whose pose fails, while the map still waits for the pose to come back (fewer than
  /// lost_frames_before_reset failures in a row), is not the next frame's KLT reference: the
  /// next frame is followed from the last tracked one, and the tracks keep their positions
  /// there. A flicker frame or a blurred one otherwise cut every track that KLT lost on it,
  /// and the map ran out of points. Past lost_frames_before_reset (a map held for its keyframe)
  /// the tracks follow frame to frame again.
  bool keep_reference_over_failed_frames = true;
  /// Live monocular input only (run.wait_when_starving off): after lost_frames_before_reset
  /// failures the map is kept while a keyframe of a tracked frame is still in flight and the
  /// last tracked frame is at most this many seconds old (0: off). That keyframe brings new
  /// points, followed into the latest frame when it merges; resetting threw it away, and a
  /// monocular restart needs seconds of parallax. Offline, a starving tracker waits for it
  /// instead; a stereo or RGB-D map restarts on one frame, and held it tracked fewer frames.
  double hold_map_for_keyframe_s = 1.0;
  /// When a keyframe's points join the tracker, those whose map point projects farther than
  /// this (pixels) from the track at the latest pose are dropped (0: off). Late keyframes
  /// (threaded mode) otherwise bring inconsistent points that make the pose jump: EuRoC at
  /// rest, threaded, moves 1.4-1.6 mm with 4 px and 3.5-10.6 mm without (docs/vo.md).
  double merge_gate_px = 4.0;
  /// When most of a returning keyframe's points miss the current pose by more than merge_gate_px,
  /// the pose first moves by the keyframe's bundle-adjustment correction (the motion since the
  /// keyframe kept) if that brings them closer: the adjustment moved its window as a whole, and
  /// the gate would otherwise drop the points it adjusted. Stereo medium_lowtexture lost frames
  /// 31-34 that way at starts 2 and 3; it fires about once a run (docs/vo.md). Needs
  /// the gate (merge_gate_px > 0).
  bool follow_keyframe_adjustment = true;
  /// When most still miss, the pose by PnP (geometry.pnp) on the merged tracks' map points is
  /// taken if at least twice as many of them lie within the gate there: in a fast turn the
  /// tracker's pose may rest on the few points it still follows, while the keyframe's points were
  /// followed from a frame that had many (live stereo difficult_normal, frame 42: 10 of 44 within
  /// 4 px, then the map lost). Needs the gate.
  bool merge_pose_by_pnp = true;
  /// Live input only (run.wait_when_starving off): a frame that follows fewer map points than
  /// run.starving_points (its mode's; not the noisy frames' higher count, where provisional
  /// points only added their depth's doubt) takes candidates into its pose too, each at a
  /// provisional position that the tracker triangulates after every tracked frame from the
  /// candidate's keyframe views and that frame (geometry.point_triangulation's checks). Offline a
  /// starving tracker waits for the keyframe in flight, which brings those points into the map;
  /// live it cannot, and a monocular map ran out of points between keyframes. Provisional points
  /// never enter the map, nor the keyframe rule's point count.
  bool provisional_points = true;
  /// Monocular, with provisional points: a starving live frame also looks for Shi-Tomasi corners away
  /// from every track and follows up to this many of them (0: off); each is triangulated from
  /// the tracked frame it was found in and the latest one and joins a starving frame's pose as
  /// a provisional point (frame_corners.h). Candidates come only with keyframes, and in a dark
  /// or fast turn they die before the next one.
  int frame_corners = 100;
  /// The same for a metric map (stereo, RGB-D; replaces frame_corners there): each new corner
  /// takes its position from the frame's own stereo match or depth, as a keyframe's new points
  /// do, and keeps it (0: off). Two-frame depths made metric live poses worse (docs/vo.md).
  int stereo_frame_corners = 100;
  /// ...the corners at least this far (pixels) from each other and from every track.
  double frame_corner_spacing_px = 12.0;
  /// When PnP / the refinement fail for want of points, a pose is still accepted from the
  /// motion prior plus at least this many agreeing observations (points + lines); 0: off.
  int min_inliers_with_prior = 5;
  /// Stereo runs: these replace geometry.pnp.min_inliers and min_inliers_with_prior. In a plain
  /// room (medium_lowtexture) frames 20-35 see 5-20 points and few lines; with 10 / 5 frames
  /// 23-34 were lost, with 6 / 4 (and init.stereo_min_points 12, the working view "fit") none is.
  /// With 3 agreeing observations a frame after a 0.6 s jump kept a pose 0.1 m off instead of
  /// relocalising (Recovery.AStereoFrameThatLosesItsPoseRelocalisesAtOnce; docs/vo.md).
  int stereo_pnp_min_inliers = 6;
  int stereo_min_inliers_with_prior = 4;
  /// After a reset, a new map started within this many seconds of the last tracked pose (and
  /// not relocalised) starts at that pose moved on by the last velocity's translation over the
  /// gap, with the last orientation: the trajectory then does not jump back by the distance
  /// travelled during a short loss (0: at the last pose).
  double extrapolate_gap_max_s = 0.5;
  /// ... the velocity being the mean step over the last this many consecutive tracked frames:
  /// one step's position is as noisy as its pose (with few points per frame, one
  /// step carried a 6-frame gap 0.12 m off; 1: the last step alone).
  int extrapolate_velocity_frames = 5;
  /// A stereo map restarted after a loss first relocalises against the last keyframes before
  /// the loss: its features matched with theirs (the keyframe matcher), PnP + RANSAC
  /// on the map points of the matches. With at least this many inliers the new map starts at
  /// that pose, in the old map's frame; otherwise at restart_pose (0: never relocalise).
  int relocalise_min_inliers = 20;
  /// Relocalisation matches with this many of the last keyframes before the loss and pools
  /// their map points: one keyframe holds only the points it saw linked.
  int relocalise_keyframes = 3;
  /// A monocular camera that lost track tries, on every frame for this many seconds after
  /// the last tracked one, to relocalise against the last keyframes before the loss (same
  /// matcher, PnP, relocalise_keyframes and relocalise_min_inliers); when it does, the old map resumes with that
  /// frame as its next keyframe and keeps its scale, instead of a two-view start at a new,
  /// arbitrary scale. Each try costs one detection and one match (0: off).
  double mono_resume_max_s = 2.0;
  /// A monocular frame whose pose fails on the map (a fast turn carries the map's points out of
  /// view before new ones can be triangulated) takes its motion from the previous frame by the
  /// essential matrix of all its KLT tracks, map points and candidates alike, with at least
  /// this many inliers; the step keeps the last velocity's length, and rotation and direction
  /// must stay near it (geometry::RelativeMotionLimits). The keyframes made meanwhile
  /// triangulate new points from these poses. Counted in stats.json as `frame_motion_poses`
  /// (0: off).
  int mono_frame_motion_min_inliers = 20;
  /// ... for at most this many frames in a row; after them the frame is lost as before.
  int mono_frame_motion_max_frames = 5;
  double mono_frame_motion_max_rotation_change_deg = 5.0;
  double mono_frame_motion_max_translation_change_deg = 45.0;
  double mono_frame_motion_translation_sigma_deg = 15.0;  ///< prior on the direction (0: none)
};

/// New keyframes: their features without a point matched with recent keyframes' points by
/// projection and descriptor (projection_search.h explains why).
struct ProjectionSearchConfig {
  bool enabled = true;
  int keyframes = 10;          ///< points seen by this many newest keyframes of the segment
  double radius_px = 5.0;      ///< around each point's projection
  double max_float_distance = 0.7;  ///< unit-norm float descriptors (SuperPoint): L2 distance
  int max_hamming = 50;        ///< binary descriptors (ORB): Hamming distance
  double ratio = 0.9;          ///< best over second-best distance among the features in the radius
};

/// Keyframe processing on the worker: matching, triangulation (geometry.point_triangulation,
/// geometry.line_triangulation), sliding-window BA (backend.bundle_adjustment).
struct MappingConfig {
  std::string matcher = "auto";   ///< auto (LightGlue if weights exist, else MNN) | lightglue | mnn
  std::string lightglue_weights = "";
  /// LightGlue's adaptive depth (early exit once this share of points is confident) and width
  /// (pruning of unmatchable points); <= 0 turns each off (the full network every time).
  double lightglue_depth_confidence = 0.95;
  double lightglue_width_confidence = 0.99;
  double mnn_max_distance = 0.7;  ///< float descriptors (unit norm): L2 distance (hloc's 0.7)
  /// Keyframe matching leaves out what KLT already connects: the new keyframe's tracked
  /// features and the previous keyframe's features they were tracked from (their matches are
  /// discarded anyway). Off: it saved ~15 % of LightGlue's time but the context those features
  /// give LightGlue mattered on ECD (Sim3 ATE 2.60 -> 9.26 %; docs/vo.md).
  bool match_untracked_only = false;
  double orb_ratio = 0.8;         ///< binary descriptors: Lowe ratio test
  int orb_max_hamming = 64;
  /// Older keyframes (outside the window) that see the window's points join the BA, fixed,
  /// to anchor it; at most this many. A monocular window's scale rests on them.
  int max_anchor_keyframes = 5;
  /// Stereo and RGB-D runs: this replaces max_anchor_keyframes. Every keyframe of a metric map
  /// measures the scale itself; fixed older keyframes add no gauge but hold the window at the
  /// scale, and the stereo pair's offset (backend.bundle_adjustment.stereo_offset_sigma_px), they
  /// were estimated with. Single thread: KITTI 01 stereo 3.12 -> 1.51 %, KITTI 06 0.05 -> 0.04 %,
  /// EuRoC 0.8 -> 0.7 mm, TUM RGB-D 3.0 mm both; synthetic stereo (nine 10 s presets) mean
  /// 1.144 -> 1.164 % (docs/vo.md).
  int stereo_max_anchor_keyframes = 0;
  /// Monocular runs with lines: smallest angle between the two back-projected planes of a new
  /// 3-D line (raises geometry.line_triangulation.min_plane_angle_deg in mono). Lines
  /// triangulated from monocular keyframes at the stereo default (2 deg) pull the scale harder:
  /// medium_lowlight mono 7.2 % at 2 deg, 4.0 % at 5 deg (docs/vo.md).
  double mono_line_min_plane_angle_deg = 5.0;
  /// Monocular runs with lines: the sliding-window BA weighs line residuals at most this much
  /// relative to points (a ceiling on backend.bundle_adjustment.line_weight in mono). Lines from
  /// short monocular baselines otherwise pull the scale in low light (docs/vo.md).
  double mono_ba_line_weight = 0.25;
  /// Monocular runs: a candidate's position in a new keyframe is aligned (LK) to its patch in
  /// the keyframe where its track began. Its observations then carry one alignment's error
  /// each, instead of the error that a frame-to-frame track adds up over its frames; a candidate
  /// that does not align within mono_align_max_shift_px (a wrong link, a track that slid) starts
  /// again from the new keyframe. Descriptor links in the dark were 16 % within 2 px of the true
  /// geometry, KLT links 44 %; aligned, 61 % and 80 % (docs/vo.md).
  bool mono_align_to_origin = true;
  /// ...on keyframes whose image noise (grey levels) reaches this: low light (synthetic normal
  /// light 0.5-2.8, low light 4.1-9). In normal light the tracks drift little, and the dropped
  /// links cost the plain room's sparse map more than the alignment gives. 0: always.
  double mono_align_min_noise = 3.5;
  double mono_align_max_shift_px = 2.0;
  int mono_align_levels = 1;             ///< LK pyramid levels above the base for the alignment
  int mono_align_cache_keyframes = 40;   ///< newest keyframes whose images are kept for it
  ProjectionSearchConfig projection_search;
};

/// Whole-pipeline switches for ablations and baselines (pllvo bench): each turns one of the
/// paper's contributions off everywhere it acts.
struct PipelineConfig {
  /// Lines at all: detection on keyframes, line optical flow, line residuals in the pose and
  /// the bundle adjustment, the line keyframe trigger. false: a points-only VO.
  bool lines = true;
  /// Lines also in monocular mode. With a single camera the lines are triangulated from
  /// keyframes a few centimetres apart and pull the scale at full BA weight (measured: off);
  /// with mapping.mono_line_min_plane_angle_deg and mapping.mono_ba_line_weight they are lower
  /// than points-only on 14 of 24 synthetic mono runs (mean 2.17 against 2.35 %), and on real data
  /// ECD keeps 57 of 149 frames instead of 34, KITTI 0.06 % instead of 0.13 % (docs/vo.md).
  bool lines_in_mono = true;
  /// How lines follow the camera between keyframes: `flow` (line optical flow, paper 3.1) or
  /// `redetect` (the usual baseline: lines detected in every frame and associated with the
  /// previous frame's lines by position, predicted by the motion prior; no flow).
  std::string line_tracking = "flow";
};

/// Plain scenes (blank walls, a door, a floor edge): a handful of point features, so the few
/// long edges there are must carry the pose. Two line options that cost accuracy where texture
/// is rich (docs/vo.md: stereo lines, aperture handling, the rule)
/// act only where it is not.
struct PlainSceneConfig {
  /// Stereo keyframes with fewer point detections than this match their lines left-right and
  /// triangulate them at once (lines.stereo), so a door edge is mapped on the keyframe that
  /// sees it, not two keyframes later. Textured keyframes keep lines.stereo.enabled (0: off).
  int max_keyframe_features = 60;
  /// Frames following fewer map points than this track lines with aperture handling
  /// (line_aperture_eigen_ratio as lines.tracker.aperture_max_eigen_ratio): samples on a plain
  /// edge keep only their motion across it (0: off).
  int max_tracked_points = 30;
  double line_aperture_eigen_ratio = 0.05;
  /// Monocular keyframes with fewer point detections than mono_max_keyframe_features and less
  /// image noise than run.noisy_frame_noise (normal light) triangulate new 3-D lines from this
  /// angle between their planes instead of mapping.mono_line_min_plane_angle_deg (0: off). In a
  /// plain room the few long edges are what the map can hold on to, and at 5 deg almost none is
  /// ever triangulated; on textured keyframes, and in low light, 2 deg lines pull the scale
  /// (docs/vo.md).
  double mono_line_min_plane_angle_deg = 2.0;
  int mono_max_keyframe_features = 120;
};

/// Known 3-D directions (vo::DirectionMap): lines that share a vanishing point in one frame
/// become a world direction; later frames' lines parallel to it constrain the camera's
/// rotation, which the map's points alone cannot hold on a few far points on one plane
/// (monocular heading drift, docs/vo.md).
struct DirectionConfig {
  bool mono = true;     ///< use them in monocular runs
  bool stereo = false;  ///< ...and in stereo runs
  /// Multiplies their residuals (pixels: distance of a segment's end from pointing at the
  /// vanishing point) in the pose refinement, with the line loss.
  double weight = 10.0;
  /// The same in the sliding-window bundle adjustment, for the keyframes' segments (0: not
  /// there): without it the window turns the map back to the points' rotation.
  double ba_weight = 10.0;
  double min_length_px = 40;  ///< shorter segments give the angle too loosely
  /// A segment belongs to a direction when, at the predicted rotation, it points within
  /// gate_deg of the direction's vanishing point and within it of no other's. An angle, not
  /// pixels: a pixel gate holds the long segments, which fix the rotation best, tightest, and
  /// lets go of them first when the rotation strays.
  double gate_deg = 4.0;
  double inlier_px = 1.0;            ///< support of a new direction's vanishing point
  int min_support = 5;               ///< segments a new direction needs in its frame
  double min_separation_deg = 5.0;   ///< between a new direction and the known ones
  /// A proposed direction is used once seen (min_support segments) in this many frames within
  /// confirm_frames + 2: a vanishing point that clutter fakes in one frame (a real 240x180
  /// camera, ecd_slider_hdr_close_149) does not come back.
  int confirm_frames = 3;
  /// Directions known before any is used: one alone may be clutter that a static scene shows
  /// again in every frame (ecd_slider_hdr_close_149: a "vertical" of 4-7 segments turned the
  /// pose 20 deg); a perpendicular pair is a room.
  int min_known = 2;
  /// Manhattan world: a new direction is perpendicular to the known ones (three at most).
  /// Without it, parallel horizontals near the horizon fit a vanishing point anywhere along
  /// it: difficult_lowlight start 6 gathered 10 directions, one 18 deg from a known one
  /// (docs/vo.md).
  bool orthogonal_only = true;
  int max_directions = 12;  ///< without orthogonal_only
};

/// RGB-D: a depth image is the metric source in place of a stereo pair. A feature with a
/// valid depth d gets the right-image observation u - f b / d of a virtual rectified pair of
/// baseline `virtual_baseline_m`, so the one-frame start, the new points and the bundle
/// adjustment are the stereo ones. The BA's pixel noise on that observation is a depth noise
/// that grows as d^2 (sigma_z = d^2 sigma_px / (f b)), as a structured-light or time-of-flight
/// sensor's does; the pair's offset is not estimated (there is no second camera).
struct DepthConfig {
  /// 0.08 m: with TUM fr3's f = 535 px, 1 px of virtual disparity is 2.3 cm of depth at 1 m and
  /// 21 cm at 3 m (ORB-SLAM3's TUM settings: f b = 40 px m).
  double virtual_baseline_m = 0.08;
  double min_m = 0.1;   ///< nearer depths are no measurement
  double max_m = 10.0;  ///< farther ones neither (a feature there waits for two-view triangulation)
  /// A feature whose 3x3 neighbourhood of valid depths spreads by more than this fraction of
  /// its own depth sits on a depth edge, where the depth pixel may belong to either side: no point.
  double max_local_spread = 0.05;
};

/// Everything else: threads, progress, output.
struct RunConfig {
  bool threaded = true;        ///< keyframe worker thread; false: deterministic single thread
  /// Threaded mode, offline input: when fewer map points than starving_points are tracked
  /// while a keyframe is still being processed, the frame waits for it instead of losing
  /// track (a live camera would drop frames then). Counted in stats.json as `starved_waits`.
  /// Likewise when the point trigger (few points, tracking quality) asks for a keyframe while
  /// the worker's queue is full. Off: tracking never waits.
  bool wait_when_starving = true;
  /// Below keyframes.min_tracked_points, so that tracking goes on with the points it has
  /// while the keyframe that the point rule asked for is processed; at that same count every
  /// point keyframe was waited for in full (docs/vo.md).
  int starving_points = 45;
  /// The same for monocular runs, where it replaces starving_points: a monocular map's scale
  /// lives on the points each keyframe triangulates, and a tracker that runs on while the
  /// keyframe it asked for is processed makes the next keyframes too close for parallax
  /// (ECD threaded: 47 frames tracked, 17.2 % ATE at 45; 56 frames, 2.60 % at 60, as a
  /// single-thread run; docs/vo.md). Stereo maps get their depth from the pair.
  int mono_starving_points = 60;
  /// ...and on their noisy frames (noisy_frame_noise) this instead: in low light a monocular
  /// tracker waits for every keyframe in flight (no frame follows 1000 map points), so a threaded
  /// run is the single-thread run. The few keyframes it did not wait for moved threaded
  /// difficult_lowlight from a 1.97 % mean over starts 0-7 (single thread) to 2.70 %. Waiting
  /// for all costs no speed where the tracker already waited for 137-143 of ~140 keyframes
  /// (medium and difficult low light), easy_lowlight 8.8 -> 6.0 frames/s (docs/vo.md).
  int mono_noisy_starving_points = 1000;
  /// Stereo frames whose image noise reaches noisy_frame_noise (grey levels, the estimate
  /// klt.denoise_min_noise reads: the suite's normal light 0.5-2.8, its low light 4.1-9) starve below
  /// noisy_starving_points instead: each noisy track holds the pose less, and in the fast dark
  /// turns a tracker that ran on without the keyframe in flight drifted (stereo
  /// difficult_lowlight starts 0-3: 2.30 / 1.30 / 1.48 / 1.43 % at 45, 1.13 / 1.21 / 1.95 / 0.48 %
  /// at 80, with normal-light speed untouched; docs/vo.md). Monocular runs keep
  /// mono_starving_points.
  int noisy_starving_points = 80;
  double noisy_frame_noise = 3.5;

  /// Tracked map points below which a frame with this image noise waits (see above).
  int starving_points_at(double image_noise) const {
    return image_noise < noisy_frame_noise ? starving_points : std::max(starving_points, noisy_starving_points);
  }
  double progress_interval_s = 2.0;  ///< wall time between progress lines (0: none)
  /// LibTorch + OpenBLAS threads for the networks (threaded runs; a single-thread run uses 1).
  /// With 2, LightGlue runs each image on its own thread (nn::TwoLanes, 1.9x faster than one)
  /// and SuperPoint splits its convolutions: on 2 cores live-rate playback then drops fewer
  /// frames (real fixtures' mean 20.8 -> 5.4 %, synthetic mono 57.5 -> 45.3 %, worker at the
  /// tracker's priority), and beside two busy processes it is as fast as one thread
  /// (docs/results.md, live rate).
  int network_threads = 2;
  /// Threaded runs: 2 runs each keyframe's point detection (SuperPoint) on a thread of its
  /// own, beside the previous keyframe's matching and bundle adjustment; 1 runs both on one
  /// keyframe thread. Single-thread runs do everything in order on the caller's thread.
  int keyframe_stages = 2;
  /// Threaded runs: the keyframe worker's threads run this many nice levels below the caller
  /// (0..19; 0: same priority), so a frame that arrives while a keyframe is being made is
  /// tracked at once instead of sharing a core with the networks. Nice levels are machine-wide:
  /// a larger value also starves the worker beside other busy processes (docs/vo.md).
  int keyframe_worker_nice = 3;
  /// Threaded runs: after following a start's or a keyframe's new tracks up to the newest frame
  /// the tracker had finished, the worker follows them through the frames the tracker finished
  /// meanwhile, at most this many more times, so the tracker has at most a frame or two left to
  /// follow itself when it takes the result (0: once, as far as the newest frame at the start).
  /// Following is the tracker's own KLT on the same frames, so the tracks are the same either way;
  /// only which thread spends the time changes (live TUM start: 4 frames, 77 ms, on the tracker).
  int worker_catch_up_rounds = 8;
};

struct VoConfig {
  FrontendConfig frontend;
  KltConfig klt;
  KeyframePolicyConfig keyframes;
  InitConfig init;
  PoseConfig pose;
  MappingConfig mapping;
  PipelineConfig pipeline;
  PlainSceneConfig plain_scene;
  DirectionConfig directions;
  DepthConfig depth;
  RunConfig run;
  geometry::GeometryConfig geometry;  ///< section `geometry:` (keys of config/geometry.yaml)
  backend::BackendConfig backend;     ///< section `backend:` (keys of config/backend.yaml)
  lines::LinesConfig lines;           ///< section `lines:` (keys of config/lines.yaml)

  /// Defaults overridden by the file; InputError names the file and key of a bad value.
  static VoConfig load(const std::filesystem::path& file);
  /// The configuration one run uses: in monocular mode pipeline.lines is off when
  /// pipeline.lines_in_mono is, new 3-D lines need mapping.mono_line_min_plane_angle_deg, and the
  /// BA's line weight is at most mapping.mono_ba_line_weight.
  VoConfig for_mode(bool stereo) const;
  void read(const ConfigNode& node);
  /// InputError (key path) for values outside their meaningful range.
  void validate(const std::filesystem::path& file = {}) const;
};

}  // namespace pllvo::vo
