#include "pllvo/vo/vo_config.h"

#include <algorithm>
#include <cmath>

#include "pllvo/camera/stereo_rectifier.h"
#include "pllvo/nn/superpoint.h"

namespace pllvo::vo {
namespace {

void read_frontend(const ConfigNode& n, FrontendConfig& c) {
  n.get("type", c.type);
  n.get("working_view", c.working_view);
  n.get("mono_working_view", c.mono_working_view);
  n.get("max_points", c.max_points);
  n.get("grid_cols", c.grid_cols);
  n.get("grid_rows", c.grid_rows);
  n.get("min_distance_px", c.min_distance_px);
  n.get("orb_levels", c.orb_levels);
  n.get("orb_scale_factor", c.orb_scale_factor);
  n.get("orb_fast_threshold", c.orb_fast_threshold);
  n.get("shitomasi_quality", c.shitomasi_quality);
  n.get("shitomasi_block_size", c.shitomasi_block_size);
  n.get("superpoint_weights", c.superpoint_weights);
  n.get("superpoint_input_scale", c.superpoint_input_scale);
  n.get("superpoint_threshold", c.superpoint_threshold);
  n.get("superpoint_adaptive_threshold", c.superpoint_adaptive_threshold);
  n.get("superpoint_nms_radius", c.superpoint_nms_radius);
  n.get("superpoint_equalize", c.superpoint_equalize);
  n.get("superpoint_conv_layout", c.superpoint_conv_layout);
  n.get("min_corner_ratio", c.min_corner_ratio);
  n.get("mono_min_corner_ratio", c.mono_min_corner_ratio);
  n.get("equalize", c.equalize);
  n.reject_unknown_keys();
}

void read_klt(const ConfigNode& n, KltConfig& c) {
  n.get("window_px", c.window_px);
  n.get("levels", c.levels);
  n.get("max_iterations", c.max_iterations);
  n.get("epsilon", c.epsilon);
  n.get("fb_threshold_px", c.fb_threshold_px);
  n.get("min_ncc", c.min_ncc);
  n.get("min_eigen_threshold", c.min_eigen_threshold);
  n.get("normalize_mean", c.normalize_mean);
  n.get("max_normalize_gain", c.max_normalize_gain);
  n.get("contrast_fallback_share", c.contrast_fallback_share);
  n.get("contrast_window_px", c.contrast_window_px);
  n.get("denoise_min_noise", c.denoise_min_noise);
  n.get("denoise_sigma_px", c.denoise_sigma_px);
  n.get("border_px", c.border_px);
  n.get("stereo_min_horizontal_share", c.stereo_min_horizontal_share);
  n.reject_unknown_keys();
}

void read_keyframes(const ConfigNode& n, KeyframePolicyConfig& c) {
  n.get("use_point_trigger", c.use_point_trigger);
  n.get("min_tracked_points", c.min_tracked_points);
  n.get("min_tracked_ratio", c.min_tracked_ratio);
  n.get("use_time_trigger", c.use_time_trigger);
  n.get("max_interval_s", c.max_interval_s);
  n.get("min_interval_s", c.min_interval_s);
  n.get("use_line_trigger", c.use_line_trigger);
  n.get("line_angle_distance_deg", c.line_angle_distance_deg);
  n.get("line_trigger_when_idle", c.line_trigger_when_idle);
  n.get("point_trigger_while_in_flight", c.point_trigger_while_in_flight);
  n.get("line_min_angles", c.line_min_angles);
  n.reject_unknown_keys();
}

void read_init(const ConfigNode& n, InitConfig& c) {
  n.get("min_points", c.min_points);
  n.get("mono_min_flow_px", c.mono_min_flow_px);
  n.get("max_frames", c.max_frames);
  n.get("stereo_min_points", c.stereo_min_points);
  n.get("min_brightness", c.min_brightness);
  n.reject_unknown_keys();
}

void read_pose(const ConfigNode& n, PoseConfig& c) {
  n.get("use_lines", c.use_lines);
  n.get("use_motion_prior", c.use_motion_prior);
  n.get("lost_frames_before_reset", c.lost_frames_before_reset);
  n.get("stereo_restart_at_once", c.stereo_restart_at_once);
  n.get("hold_map_for_keyframe_s", c.hold_map_for_keyframe_s);
  n.get("keep_reference_over_failed_frames", c.keep_reference_over_failed_frames);
  n.get("merge_gate_px", c.merge_gate_px);
  n.get("provisional_points", c.provisional_points);
  n.get("frame_corners", c.frame_corners);
  n.get("stereo_frame_corners", c.stereo_frame_corners);
  n.get("frame_corner_spacing_px", c.frame_corner_spacing_px);
  n.get("follow_keyframe_adjustment", c.follow_keyframe_adjustment);
  n.get("merge_pose_by_pnp", c.merge_pose_by_pnp);
  n.get("min_inliers_with_prior", c.min_inliers_with_prior);
  n.get("stereo_pnp_min_inliers", c.stereo_pnp_min_inliers);
  n.get("stereo_min_inliers_with_prior", c.stereo_min_inliers_with_prior);
  n.get("extrapolate_gap_max_s", c.extrapolate_gap_max_s);
  n.get("extrapolate_velocity_frames", c.extrapolate_velocity_frames);
  n.get("relocalise_min_inliers", c.relocalise_min_inliers);
  n.get("relocalise_keyframes", c.relocalise_keyframes);
  n.get("mono_resume_max_s", c.mono_resume_max_s);
  n.get("mono_frame_motion_min_inliers", c.mono_frame_motion_min_inliers);
  n.get("mono_frame_motion_max_frames", c.mono_frame_motion_max_frames);
  n.get("mono_frame_motion_max_rotation_change_deg", c.mono_frame_motion_max_rotation_change_deg);
  n.get("mono_frame_motion_max_translation_change_deg", c.mono_frame_motion_max_translation_change_deg);
  n.get("mono_frame_motion_translation_sigma_deg", c.mono_frame_motion_translation_sigma_deg);
  n.reject_unknown_keys();
}

void read_mapping(const ConfigNode& n, MappingConfig& c) {
  n.get("matcher", c.matcher);
  n.get("lightglue_weights", c.lightglue_weights);
  n.get("lightglue_depth_confidence", c.lightglue_depth_confidence);
  n.get("lightglue_width_confidence", c.lightglue_width_confidence);
  n.get("mnn_max_distance", c.mnn_max_distance);
  n.get("match_untracked_only", c.match_untracked_only);
  n.get("orb_ratio", c.orb_ratio);
  n.get("orb_max_hamming", c.orb_max_hamming);
  n.get("max_anchor_keyframes", c.max_anchor_keyframes);
  n.get("stereo_max_anchor_keyframes", c.stereo_max_anchor_keyframes);
  n.get("mono_line_min_plane_angle_deg", c.mono_line_min_plane_angle_deg);
  n.get("mono_ba_line_weight", c.mono_ba_line_weight);
  n.get("mono_align_to_origin", c.mono_align_to_origin);
  n.get("mono_align_min_noise", c.mono_align_min_noise);
  n.get("mono_align_max_shift_px", c.mono_align_max_shift_px);
  n.get("mono_align_levels", c.mono_align_levels);
  n.get("mono_align_cache_keyframes", c.mono_align_cache_keyframes);
  const ConfigNode ps = n.child("projection_search");
  ps.get("enabled", c.projection_search.enabled);
  ps.get("keyframes", c.projection_search.keyframes);
  ps.get("radius_px", c.projection_search.radius_px);
  ps.get("max_float_distance", c.projection_search.max_float_distance);
  ps.get("max_hamming", c.projection_search.max_hamming);
  ps.get("ratio", c.projection_search.ratio);
  ps.reject_unknown_keys();
  n.reject_unknown_keys();
}

void read_pipeline(const ConfigNode& n, PipelineConfig& c) {
  n.get("lines", c.lines);
  n.get("lines_in_mono", c.lines_in_mono);
  n.get("line_tracking", c.line_tracking);
  n.reject_unknown_keys();
}

void read_plain_scene(const ConfigNode& n, PlainSceneConfig& c) {
  n.get("max_keyframe_features", c.max_keyframe_features);
  n.get("max_tracked_points", c.max_tracked_points);
  n.get("line_aperture_eigen_ratio", c.line_aperture_eigen_ratio);
  n.get("mono_line_min_plane_angle_deg", c.mono_line_min_plane_angle_deg);
  n.get("mono_max_keyframe_features", c.mono_max_keyframe_features);
  n.reject_unknown_keys();
}

void read_depth(const ConfigNode& n, DepthConfig& c) {
  n.get("virtual_baseline_m", c.virtual_baseline_m);
  n.get("min_m", c.min_m);
  n.get("max_m", c.max_m);
  n.get("max_local_spread", c.max_local_spread);
  n.reject_unknown_keys();
}

void read_directions(const ConfigNode& n, DirectionConfig& c) {
  n.get("mono", c.mono);
  n.get("stereo", c.stereo);
  n.get("weight", c.weight);
  n.get("ba_weight", c.ba_weight);
  n.get("min_length_px", c.min_length_px);
  n.get("gate_deg", c.gate_deg);
  n.get("inlier_px", c.inlier_px);
  n.get("min_support", c.min_support);
  n.get("min_separation_deg", c.min_separation_deg);
  n.get("confirm_frames", c.confirm_frames);
  n.get("min_known", c.min_known);
  n.get("orthogonal_only", c.orthogonal_only);
  n.get("max_directions", c.max_directions);
  n.reject_unknown_keys();
}

void read_run(const ConfigNode& n, RunConfig& c) {
  n.get("threaded", c.threaded);
  n.get("wait_when_starving", c.wait_when_starving);
  n.get("starving_points", c.starving_points);
  n.get("mono_starving_points", c.mono_starving_points);
  n.get("mono_noisy_starving_points", c.mono_noisy_starving_points);
  n.get("noisy_starving_points", c.noisy_starving_points);
  n.get("noisy_frame_noise", c.noisy_frame_noise);
  n.get("network_threads", c.network_threads);
  n.get("keyframe_stages", c.keyframe_stages);
  n.get("keyframe_worker_nice", c.keyframe_worker_nice);
  n.get("worker_catch_up_rounds", c.worker_catch_up_rounds);
  n.get("progress_interval_s", c.progress_interval_s);
  n.reject_unknown_keys();
}

void require(bool ok, const std::filesystem::path& file, const std::string& key,
             const std::string& message) {
  if (!ok) throw InputError(file, key, message);
}

}  // namespace

VoConfig VoConfig::for_mode(bool stereo) const {
  VoConfig c = *this;
  if (!stereo && !pipeline.lines_in_mono) c.pipeline.lines = false;
  if (stereo) {
    c.geometry.pnp.min_inliers = pose.stereo_pnp_min_inliers;
    c.pose.min_inliers_with_prior = pose.stereo_min_inliers_with_prior;
    c.pose.frame_corners = pose.stereo_frame_corners;
    c.mapping.max_anchor_keyframes = mapping.stereo_max_anchor_keyframes;
  } else {
    auto& angle = c.geometry.line_triangulation.min_plane_angle_deg;
    angle = std::max(angle, mapping.mono_line_min_plane_angle_deg);
    auto& weight = c.backend.bundle_adjustment.line_weight;
    weight = std::min(weight, mapping.mono_ba_line_weight);
    c.run.starving_points = run.mono_starving_points;
    c.run.noisy_starving_points = run.mono_noisy_starving_points;
    c.frontend.min_corner_ratio = frontend.mono_min_corner_ratio;
    c.frontend.working_view = frontend.mono_working_view;
  }
  return c;
}

VoConfig VoConfig::load(const std::filesystem::path& file) {
  VoConfig config;
  config.read(ConfigNode::load_file(file));
  config.validate(file);
  return config;
}

void VoConfig::read(const ConfigNode& node) {
  read_frontend(node.child("frontend"), frontend);
  read_klt(node.child("klt"), klt);
  read_keyframes(node.child("keyframes"), keyframes);
  read_init(node.child("init"), init);
  read_pose(node.child("pose"), pose);
  read_mapping(node.child("mapping"), mapping);
  read_pipeline(node.child("pipeline"), pipeline);
  read_plain_scene(node.child("plain_scene"), plain_scene);
  read_directions(node.child("directions"), directions);
  read_depth(node.child("depth"), depth);
  read_run(node.child("run"), run);
  geometry.load(node.child("geometry"));
  backend.load(node.child("backend"));
  lines.load(node.child("lines"));
  node.reject_unknown_keys();
}

void VoConfig::validate(const std::filesystem::path& file) const {
  const auto& f = frontend;
  require(f.type == "auto" || f.type == "superpoint" || f.type == "orb" || f.type == "shitomasi", file,
          "frontend.type", "must be auto, superpoint, orb or shitomasi (got '" + f.type + "')");
  for (const auto& [key, view] : {std::pair{"frontend.working_view", f.working_view},
                                  std::pair{"frontend.mono_working_view", f.mono_working_view}})
    require(camera::working_view_named(view).has_value(), file, key,
            "must be calibrated, whole or fit (got '" + view + "')");
  require(f.max_points > 0, file, "frontend.max_points", "must be positive");
  require(f.grid_cols > 0 && f.grid_rows > 0, file, "frontend.grid_cols", "grid must be at least 1x1");
  require(f.superpoint_input_scale > 0 && f.superpoint_input_scale <= 1, file,
          "frontend.superpoint_input_scale", "must be in (0, 1]");
  nn::SuperPointConfig network;  // the network's own rule for the layouts it has
  network.conv_layout = f.superpoint_conv_layout;
  const auto [network_key, problem] = network.problem();
  require(network_key != "conv_layout", file, "frontend.superpoint_conv_layout",
          problem + " (got '" + f.superpoint_conv_layout + "')");
  require(run.network_threads >= 1 && run.network_threads <= 64, file, "run.network_threads", "must be in [1, 64]");
  require(run.starving_points >= 0, file, "run.starving_points", "must not be negative");
  require(run.mono_starving_points >= 0, file, "run.mono_starving_points", "must not be negative");
  require(run.mono_noisy_starving_points >= 0, file, "run.mono_noisy_starving_points", "must not be negative");
  require(run.noisy_starving_points >= 0, file, "run.noisy_starving_points", "must not be negative");
  require(run.noisy_frame_noise > 0 && std::isfinite(run.noisy_frame_noise), file, "run.noisy_frame_noise",
          "must be positive");
  require(run.keyframe_stages == 1 || run.keyframe_stages == 2, file, "run.keyframe_stages", "must be 1 or 2");
  require(run.keyframe_worker_nice >= 0 && run.keyframe_worker_nice <= 19, file, "run.keyframe_worker_nice", "must be in [0, 19]");
  require(run.worker_catch_up_rounds >= 0 && run.worker_catch_up_rounds <= 100, file, "run.worker_catch_up_rounds",
          "must be in [0, 100]");
  require(klt.window_px >= 5 && klt.window_px % 2 == 1, file, "klt.window_px", "must be odd and >= 5");
  require(klt.levels >= 0 && klt.levels <= 6, file, "klt.levels", "must be in [0, 6]");
  require(klt.fb_threshold_px > 0, file, "klt.fb_threshold_px", "must be positive");
  require(klt.contrast_fallback_share >= 0 && klt.contrast_fallback_share <= 1, file, "klt.contrast_fallback_share",
          "must be in [0, 1]");
  require(klt.contrast_window_px >= 3, file, "klt.contrast_window_px", "must be at least 3");
  require(klt.denoise_min_noise >= 0, file, "klt.denoise_min_noise", "must be >= 0 (0: off)");
  require(klt.denoise_sigma_px >= 0 && klt.denoise_sigma_px <= 5, file, "klt.denoise_sigma_px", "must be in [0, 5]");
  require(keyframes.min_tracked_ratio >= 0 && keyframes.min_tracked_ratio <= 1, file,
          "keyframes.min_tracked_ratio", "must be in [0, 1]");
  require(keyframes.max_interval_s > 0, file, "keyframes.max_interval_s", "must be positive");
  require(keyframes.min_interval_s >= 0 && keyframes.min_interval_s <= keyframes.max_interval_s, file,
          "keyframes.min_interval_s", "must be in [0, max_interval_s]");
  require(keyframes.line_angle_distance_deg > 0 && keyframes.line_angle_distance_deg <= 90, file,
          "keyframes.line_angle_distance_deg", "must be in (0, 90]");
  require(pose.lost_frames_before_reset >= 1, file, "pose.lost_frames_before_reset", "must be at least 1");
  require(pose.frame_corners >= 0, file, "pose.frame_corners", "must not be negative (0: off)");
  require(pose.stereo_frame_corners >= 0, file, "pose.stereo_frame_corners", "must not be negative (0: off)");
  require(pose.frame_corner_spacing_px >= 1 && std::isfinite(pose.frame_corner_spacing_px), file,
          "pose.frame_corner_spacing_px", "must be at least 1");
  require(pose.hold_map_for_keyframe_s >= 0 && std::isfinite(pose.hold_map_for_keyframe_s), file,
          "pose.hold_map_for_keyframe_s", "must be >= 0 (0: off)");
  require(pose.extrapolate_gap_max_s >= 0 && std::isfinite(pose.extrapolate_gap_max_s), file,
          "pose.extrapolate_gap_max_s", "must be >= 0 (0: off)");
  require(pose.extrapolate_velocity_frames >= 1, file, "pose.extrapolate_velocity_frames", "must be >= 1");
  require(pose.relocalise_min_inliers == 0 || pose.relocalise_min_inliers >= 6, file, "pose.relocalise_min_inliers",
          "must be 0 (off) or at least 6");
  require(pose.stereo_pnp_min_inliers >= 4, file, "pose.stereo_pnp_min_inliers", "must be at least 4 (PnP's minimal set + 1)");
  require(pose.stereo_min_inliers_with_prior >= 0, file, "pose.stereo_min_inliers_with_prior", "must not be negative (0: off)");
  require(pose.relocalise_keyframes >= 1, file, "pose.relocalise_keyframes", "must be at least 1");
  require(pose.mono_resume_max_s >= 0 && std::isfinite(pose.mono_resume_max_s), file, "pose.mono_resume_max_s",
          "must be >= 0 (0: off)");
  require(pose.mono_frame_motion_min_inliers == 0 || pose.mono_frame_motion_min_inliers >= 8, file,
          "pose.mono_frame_motion_min_inliers", "must be 0 (off) or at least 8 (the essential matrix's sample)");
  require(pose.mono_frame_motion_max_frames >= 1, file, "pose.mono_frame_motion_max_frames", "must be at least 1");
  require(pose.mono_frame_motion_max_rotation_change_deg > 0 && pose.mono_frame_motion_max_rotation_change_deg <= 180,
          file, "pose.mono_frame_motion_max_rotation_change_deg", "must be in (0, 180]");
  require(pose.mono_frame_motion_max_translation_change_deg > 0 &&
              pose.mono_frame_motion_max_translation_change_deg <= 180,
          file, "pose.mono_frame_motion_max_translation_change_deg", "must be in (0, 180]");
  require(pose.mono_frame_motion_translation_sigma_deg >= 0 && pose.mono_frame_motion_translation_sigma_deg <= 180,
          file, "pose.mono_frame_motion_translation_sigma_deg", "must be in [0, 180] (0: no prior)");
  require(init.min_points >= 8, file, "init.min_points", "must be at least 8");
  require(mapping.matcher == "auto" || mapping.matcher == "lightglue" || mapping.matcher == "mnn", file,
          "mapping.matcher", "must be auto, lightglue or mnn");
  require(pipeline.line_tracking == "flow" || pipeline.line_tracking == "redetect", file,
          "pipeline.line_tracking", "must be flow or redetect (got '" + pipeline.line_tracking + "')");
  const auto& d = directions;
  require(d.weight > 0, file, "directions.weight", "must be positive");
  require(d.ba_weight >= 0, file, "directions.ba_weight", "must be >= 0 (0: off)");
  require(d.min_length_px > 0, file, "directions.min_length_px", "must be positive");
  require(d.gate_deg > 0 && d.gate_deg < 45, file, "directions.gate_deg", "must be in (0, 45)");
  require(d.inlier_px > 0, file, "directions.inlier_px", "must be positive");
  require(d.min_support >= 3, file, "directions.min_support", "must be >= 3 (two segments always meet)");
  require(d.min_separation_deg > 0 && d.min_separation_deg < 90, file, "directions.min_separation_deg",
          "must be in (0, 90)");
  require(d.min_known >= 1, file, "directions.min_known", "must be at least 1");
  require(d.confirm_frames >= 1, file, "directions.confirm_frames", "must be at least 1");
  require(d.max_directions > 0, file, "directions.max_directions", "must be positive");
  require(depth.virtual_baseline_m > 0, file, "depth.virtual_baseline_m", "must be > 0");
  require(depth.min_m > 0 && depth.max_m > depth.min_m, file, "depth.min_m",
          "must be > 0 and below depth.max_m");
  require(depth.max_local_spread > 0, file, "depth.max_local_spread", "must be > 0");
  require(plain_scene.max_keyframe_features >= 0, file, "plain_scene.max_keyframe_features", "must be >= 0 (0: off)");
  require(plain_scene.max_tracked_points >= 0, file, "plain_scene.max_tracked_points", "must be >= 0 (0: off)");
  require(plain_scene.line_aperture_eigen_ratio > 0 && plain_scene.line_aperture_eigen_ratio < 1, file,
          "plain_scene.line_aperture_eigen_ratio", "must be in (0, 1)");
  require(plain_scene.mono_line_min_plane_angle_deg >= 0 && plain_scene.mono_line_min_plane_angle_deg < 90, file,
          "plain_scene.mono_line_min_plane_angle_deg", "must be in [0, 90) (0: off)");
  require(plain_scene.mono_max_keyframe_features >= 0, file, "plain_scene.mono_max_keyframe_features",
          "must be >= 0 (0: off)");
  require(mapping.max_anchor_keyframes >= 0, file, "mapping.max_anchor_keyframes", "must not be negative");
  require(mapping.stereo_max_anchor_keyframes >= 0, file, "mapping.stereo_max_anchor_keyframes",
          "must not be negative");
  require(mapping.mono_line_min_plane_angle_deg >= 0 && mapping.mono_line_min_plane_angle_deg < 90, file,
          "mapping.mono_line_min_plane_angle_deg", "must be in [0, 90)");
  require(mapping.mono_ba_line_weight >= 0, file, "mapping.mono_ba_line_weight", "must not be negative");
  const auto& ps = mapping.projection_search;
  require(ps.keyframes >= 1, file, "mapping.projection_search.keyframes", "must be >= 1");
  require(ps.radius_px > 0, file, "mapping.projection_search.radius_px", "must be > 0");
  require(ps.max_float_distance > 0, file, "mapping.projection_search.max_float_distance", "must be > 0");
  require(ps.max_hamming > 0, file, "mapping.projection_search.max_hamming", "must be > 0");
  require(ps.ratio > 0 && ps.ratio <= 1, file, "mapping.projection_search.ratio", "must be in (0, 1]");
  require(mapping.mono_align_min_noise >= 0, file, "mapping.mono_align_min_noise", "must not be negative");
  require(mapping.mono_align_max_shift_px > 0, file, "mapping.mono_align_max_shift_px", "must be positive");
  require(mapping.mono_align_levels >= 0, file, "mapping.mono_align_levels", "must not be negative");
  require(mapping.mono_align_cache_keyframes >= 1, file, "mapping.mono_align_cache_keyframes", "must be at least 1");
  require(klt.min_ncc >= -1 && klt.min_ncc <= 1, file, "klt.min_ncc", "must be in [-1, 1]");
  require(frontend.min_corner_ratio >= 0 && frontend.min_corner_ratio < 1, file, "frontend.min_corner_ratio",
          "must be in [0, 1) (0: off)");
  require(frontend.mono_min_corner_ratio >= 0 && frontend.mono_min_corner_ratio < 1, file,
          "frontend.mono_min_corner_ratio", "must be in [0, 1) (0: off)");
  require(klt.stereo_min_horizontal_share >= 0 && klt.stereo_min_horizontal_share < 1, file,
          "klt.stereo_min_horizontal_share", "must be in [0, 1) (0: off)");
}

}  // namespace pllvo::vo
