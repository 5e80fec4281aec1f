#pragma once
// Everything that defines a synthetic sequence, as plain data with documented defaults.
// The defaults describe the "medium_normal" preset; config/synth.yaml lists every key.
// A spec and its seed determine every byte of the output.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "pllvo/common/yaml_config.h"

namespace pllvo::synth {

/// The camera (rig): EuRoC cam0 intrinsics and distortion by default.
struct CameraSpec {
  int width = 752;
  int height = 480;
  double fx = 458.654, fy = 457.296, cx = 367.215, cy = 248.375;
  /// radial-tangential k1 k2 p1 p2 [k3]; empty = ideal pinhole.
  std::vector<double> distortion = {-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05};
  double rate_hz = 20;
  /// Adds cam1: the same camera shifted by `baseline_m` along cam0's x axis (rectified pair).
  bool stereo = false;
  double baseline_m = 0.11;
  /// Pose of cam0 in the body frame (EuRoC's T_BS); the ground truth is T_world_body.
  Eigen::Isometry3d T_body_cam0 = Eigen::Isometry3d::Identity();
};

/// Drone-like 6-DoF motion inside the scene's free space (levels like EuRoC's).
struct MotionSpec {
  double mean_speed = 0.8;         ///< m/s, average over the sequence
  double mean_angular_rate = 0.6;  ///< rad/s, average over the sequence
  double yaw_swing_deg = 35;       ///< amplitude of the yaw swings around the drift
  double yaw_drift = 0.4;          ///< share of the yaw motion that turns steadily round the room
  double pitch_deg = 18;           ///< peak pitch (look up/down)
  double roll_deg = 10;            ///< peak roll
  double shake_m = 0.01;           ///< amplitude of fast position jitter (aggressive flight)
  double shake_deg = 0.5;          ///< amplitude of fast angular jitter
  double shake_hz = 1.5;           ///< frequency of the jitter
};

/// Scene illumination over time and the camera's auto exposure.
struct LightingSpec {
  /// normal | low_light | exposure_gradual | exposure_sudden | flicker | light_off
  std::string mode = "normal";
  double illumination = 1.0;        ///< light level relative to the nominal office
  double low_light_level = 0.005;   ///< light level in mode low_light
  double flicker_hz = 107;          ///< lamp modulation frequency (beats with the frame rate)
  double flicker_depth = 0.6;       ///< modulation depth of the lamps (0..1)
  double gradual_period_s = 8;      ///< exposure_gradual: period of the exposure sweep
  double gradual_factor = 3;        ///< exposure_gradual: sweep between 1/f and f
  double sudden_interval_s = 3;     ///< exposure_sudden: mean time between exposure jumps
  double sudden_factor = 2.5;       ///< exposure_sudden: size of one jump
  double light_off_at = 0.5;        ///< light_off: switch time as a fraction of the duration
  double ae_time_constant_s = 0.6;  ///< auto exposure reacts with this first-order lag
};

/// Global-shutter sensor and optics.
struct SensorSpec {
  double sensitivity = 3300;      ///< electrons per ms at unit radiance (mean wall ~0.3)
  double exposure_ms = 3;         ///< auto exposure's target exposure at illumination 1
  double min_exposure_ms = 0.05;
  double max_exposure_ms = 15;
  double max_gain = 8;            ///< analogue gain used once exposure is at its maximum
  double full_well_e = 8000;
  double electrons_per_dn = 31.4;  ///< at gain 1 (full well -> 255)
  double read_noise_e = 6;
  double vignetting = 0.5;        ///< 0: none, 1: full cos^4 falloff
  double psf_sigma_px = 0.6;      ///< optical blur (Gaussian sigma in pixels); 0: none
  /// Samples per pixel side (a pixel integrates over its area); 1: one at its centre, which
  /// draws stair steps and broken dashes on edges: corners that no real camera sees.
  int supersample = 1;
  bool motion_blur = true;
  /// "flow": a few renders, each averaged along every pixel's own image motion (fast);
  /// "renders": one full render per sub-exposure (the reference; 3-8x slower in low light).
  std::string blur_method = "flow";
  double blur_step_px = 2.0;      ///< renders: at most this image motion between sub-exposures
  double blur_render_px = 64.0;   ///< flow: at most this image motion covered by one render
  double blur_sample_px = 1.0;    ///< flow: spacing of the samples along each pixel's path...
  int blur_max_samples = 32;      ///< flow: ...up to this many (longer paths: sparser samples)
  int max_subframes = 15;         ///< renders per frame at most
  double near_m = 0.05;           ///< near clipping plane
};

/// The built environment.
struct SceneSpec {
  std::string layout = "room";   ///< room | corridor
  std::string texture = "rich";  ///< rich | low (plain walls: lines carry the geometry)
  double length_m = 8;           ///< along x (room) or the corridor's axis
  double width_m = 6;
  double height_m = 3;
  int shelves = 3;
  int wall_boxes = 6;            ///< boxes and stacks against the walls
  int floor_boxes = 3;           ///< low boxes in the middle of the room
  int doors = 2;
  int windows = 2;
  int posters = 6;
  int ceiling_lights = 6;
  double clearance_m = 0.8;      ///< minimum distance from the camera to any surface
  double texels_per_m = 200;     ///< texture resolution of walls, floor and ceiling
  double window_light = 1.0;     ///< strength of daylight through the windows (light_off keeps it)
};

struct OutputSpec {
  bool lines = false;                ///< write mav0/camN/lines/<ns>.csv and mav0/lines3d.csv
  bool depth = false;                ///< write mav0/camN/depth/<ns>.png (uint16 mm)
  double groundtruth_rate_hz = 200;  ///< state_groundtruth_estimate0 rate (EuRoC: 200)
  int64_t start_ns = 1500000000000000000;  ///< timestamp of the first frame
  double min_segment_px = 8;         ///< shorter visible pieces of 3-D edges are dropped
};

struct SequenceSpec {
  std::string name = "custom";
  uint64_t seed = 1;
  double duration_s = 30;
  CameraSpec camera;
  MotionSpec motion;
  LightingSpec lighting;
  SensorSpec sensor;
  SceneSpec scene;
  OutputSpec output;

  size_t num_frames() const;
  double frame_time(size_t i) const { return static_cast<double>(i) / camera.rate_hz; }
};

/// Throws InputError (naming `file`/key when given) for values the generator cannot use.
void validate(const SequenceSpec& spec, const std::filesystem::path& file = {});

/// Overrides the fields named in `node` (mapping with seed, duration_s, camera, motion, ...).
/// Unknown keys and wrong types raise InputError naming the key.
void apply_yaml(const ConfigNode& node, SequenceSpec& spec);
/// Loads a spec: starts from `preset:` when the file names one, else from the defaults.
SequenceSpec load_spec(const std::filesystem::path& file);
/// Every field, as YAML that load_spec() reads back to the same spec.
std::string to_yaml(const SequenceSpec& spec);

// ---------------------------------------------------------------- presets

struct PresetInfo {
  std::string name;
  std::string description;
  bool in_suite;
};

/// easy | medium | difficult (like EuRoC's levels: speed, turn rate, aggressiveness).
MotionSpec motion_level(const std::string& level);
/// All presets: <motion>_<lighting> for motion easy|medium|difficult and lighting
/// normal|lowlight|flicker|gradual|sudden|lightoff|lowtexture, plus corridor_<motion>_normal.
std::vector<PresetInfo> presets();
/// The names in the standard suite (>= 6 sequences).
std::vector<std::string> suite_presets();
/// The spec of a preset (name set, seed 1, default duration); InputError for an unknown name.
SequenceSpec preset(const std::string& name);

}  // namespace pllvo::synth
