#include "pllvo/synth/spec.h"

#include <cmath>

#include <yaml-cpp/yaml.h>

#include "pllvo/common/error.h"

namespace pllvo::synth {

namespace {

const std::vector<std::string> kLightingModes = {"normal",           "low_light", "exposure_gradual",
                                                 "exposure_sudden",  "flicker",   "light_off"};

template <typename T>
bool one_of(const T& value, const std::vector<T>& allowed) {
  for (const auto& a : allowed)
    if (a == value) return true;
  return false;
}

void read_pose(const ConfigNode& node, const std::string& key, Eigen::Isometry3d& T) {
  if (!node.has(key)) return;
  std::vector<double> m;
  node.get(key, m);
  if (m.size() != 16) throw InputError(node.file(), node.path(key), "expected 16 numbers (4x4 row-major)");
  Eigen::Matrix4d M;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) M(r, c) = m[4 * r + c];
  const Eigen::Matrix3d R = M.topLeftCorner<3, 3>();
  if ((R * R.transpose() - Eigen::Matrix3d::Identity()).norm() > 1e-6 || R.determinant() < 0 ||
      (M.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).norm() > 1e-12)
    throw InputError(node.file(), node.path(key), "not a rigid transform");
  T.matrix() = M;
}

void read_camera(const ConfigNode& n, CameraSpec& c) {
  n.get("width", c.width);
  n.get("height", c.height);
  n.get("fx", c.fx);
  n.get("fy", c.fy);
  n.get("cx", c.cx);
  n.get("cy", c.cy);
  n.get("distortion", c.distortion);
  n.get("rate_hz", c.rate_hz);
  n.get("stereo", c.stereo);
  n.get("baseline_m", c.baseline_m);
  read_pose(n, "T_body_cam0", c.T_body_cam0);
  n.reject_unknown_keys();
}

void read_motion(const ConfigNode& n, MotionSpec& m) {
  if (n.has("level")) m = motion_level(n.require<std::string>("level"));
  n.get("mean_speed", m.mean_speed);
  n.get("mean_angular_rate", m.mean_angular_rate);
  n.get("yaw_swing_deg", m.yaw_swing_deg);
  n.get("yaw_drift", m.yaw_drift);
  n.get("pitch_deg", m.pitch_deg);
  n.get("roll_deg", m.roll_deg);
  n.get("shake_m", m.shake_m);
  n.get("shake_deg", m.shake_deg);
  n.get("shake_hz", m.shake_hz);
  n.reject_unknown_keys();
}

void read_lighting(const ConfigNode& n, LightingSpec& l) {
  n.get("mode", l.mode);
  n.get("illumination", l.illumination);
  n.get("low_light_level", l.low_light_level);
  n.get("flicker_hz", l.flicker_hz);
  n.get("flicker_depth", l.flicker_depth);
  n.get("gradual_period_s", l.gradual_period_s);
  n.get("gradual_factor", l.gradual_factor);
  n.get("sudden_interval_s", l.sudden_interval_s);
  n.get("sudden_factor", l.sudden_factor);
  n.get("light_off_at", l.light_off_at);
  n.get("ae_time_constant_s", l.ae_time_constant_s);
  n.reject_unknown_keys();
}

void read_sensor(const ConfigNode& n, SensorSpec& s) {
  n.get("sensitivity", s.sensitivity);
  n.get("exposure_ms", s.exposure_ms);
  n.get("min_exposure_ms", s.min_exposure_ms);
  n.get("max_exposure_ms", s.max_exposure_ms);
  n.get("max_gain", s.max_gain);
  n.get("full_well_e", s.full_well_e);
  n.get("electrons_per_dn", s.electrons_per_dn);
  n.get("read_noise_e", s.read_noise_e);
  n.get("vignetting", s.vignetting);
  n.get("psf_sigma_px", s.psf_sigma_px);
  n.get("supersample", s.supersample);
  n.get("motion_blur", s.motion_blur);
  n.get("blur_method", s.blur_method);
  n.get("blur_step_px", s.blur_step_px);
  n.get("blur_render_px", s.blur_render_px);
  n.get("blur_sample_px", s.blur_sample_px);
  n.get("blur_max_samples", s.blur_max_samples);
  n.get("max_subframes", s.max_subframes);
  n.get("near_m", s.near_m);
  n.reject_unknown_keys();
}

void read_scene(const ConfigNode& n, SceneSpec& s) {
  n.get("layout", s.layout);
  n.get("texture", s.texture);
  n.get("length_m", s.length_m);
  n.get("width_m", s.width_m);
  n.get("height_m", s.height_m);
  n.get("shelves", s.shelves);
  n.get("wall_boxes", s.wall_boxes);
  n.get("floor_boxes", s.floor_boxes);
  n.get("doors", s.doors);
  n.get("windows", s.windows);
  n.get("posters", s.posters);
  n.get("ceiling_lights", s.ceiling_lights);
  n.get("clearance_m", s.clearance_m);
  n.get("texels_per_m", s.texels_per_m);
  n.get("window_light", s.window_light);
  n.reject_unknown_keys();
}

void read_output(const ConfigNode& n, OutputSpec& o) {
  n.get("lines", o.lines);
  n.get("depth", o.depth);
  n.get("groundtruth_rate_hz", o.groundtruth_rate_hz);
  n.get("start_ns", o.start_ns);
  n.get("min_segment_px", o.min_segment_px);
  n.reject_unknown_keys();
}

// Each check names the YAML key it is about, so a bad file points at the line to fix.
struct Checker {
  const std::filesystem::path& file;
  void operator()(bool ok, const std::string& key, const std::string& what) const {
    if (ok) return;
    if (file.empty()) throw InputError("synth: " + key + ": " + what);
    throw InputError(file, key, what);
  }
};

}  // namespace

size_t SequenceSpec::num_frames() const {
  return static_cast<size_t>(std::floor(duration_s * camera.rate_hz + 1e-9)) + 1;
}

void validate(const SequenceSpec& s, const std::filesystem::path& file) {
  const Checker check{file};
  check(std::isfinite(s.duration_s) && s.duration_s > 0 && s.duration_s <= 3600, "duration_s",
        "must be in (0, 3600] seconds");
  const auto& c = s.camera;
  check(c.width >= 16 && c.height >= 16 && c.width <= 8192 && c.height <= 8192, "camera.width",
        "image size must be within 16..8192 pixels");
  check(c.fx > 0 && c.fy > 0 && std::isfinite(c.cx) && std::isfinite(c.cy), "camera.fx",
        "focal lengths must be positive and the principal point finite");
  check(c.distortion.empty() || c.distortion.size() == 4 || c.distortion.size() == 5,
        "camera.distortion", "needs 0, 4 or 5 radtan coefficients (k1 k2 p1 p2 [k3])");
  check(c.rate_hz > 0 && c.rate_hz <= 1000, "camera.rate_hz", "must be in (0, 1000]");
  check(!c.stereo || (c.baseline_m > 0 && c.baseline_m < 2), "camera.baseline_m",
        "must be in (0, 2) metres");
  const auto& m = s.motion;
  check(m.mean_speed >= 0 && m.mean_speed <= 5, "motion.mean_speed", "must be in [0, 5] m/s");
  check(m.mean_angular_rate >= 0 && m.mean_angular_rate <= 5, "motion.mean_angular_rate",
        "must be in [0, 5] rad/s");
  check(m.pitch_deg >= 0 && m.pitch_deg <= 60, "motion.pitch_deg", "must be in [0, 60]");
  check(m.roll_deg >= 0 && m.roll_deg <= 60, "motion.roll_deg", "must be in [0, 60]");
  check(m.yaw_swing_deg >= 0 && m.yaw_swing_deg <= 180, "motion.yaw_swing_deg", "must be in [0, 180]");
  check(m.yaw_drift >= 0 && m.yaw_drift <= 1, "motion.yaw_drift", "must be in [0, 1]");
  check(m.shake_m >= 0 && m.shake_m <= 0.2, "motion.shake_m", "must be in [0, 0.2]");
  check(m.shake_deg >= 0 && m.shake_deg <= 10, "motion.shake_deg", "must be in [0, 10]");
  check(m.shake_hz > 0 && m.shake_hz <= 20, "motion.shake_hz", "must be in (0, 20]");
  const auto& l = s.lighting;
  check(one_of(l.mode, kLightingModes), "lighting.mode",
        "unknown mode '" + l.mode +
            "' (normal, low_light, exposure_gradual, exposure_sudden, flicker, light_off)");
  check(l.illumination > 0 && l.low_light_level > 0, "lighting.illumination", "must be positive");
  check(l.flicker_depth >= 0 && l.flicker_depth <= 1 && l.flicker_hz > 0, "lighting.flicker_depth",
        "depth must be in [0, 1] and the frequency positive");
  check(l.gradual_period_s > 0 && l.gradual_factor >= 1, "lighting.gradual_factor",
        "needs period > 0 and factor >= 1");
  check(l.sudden_interval_s > 0 && l.sudden_factor >= 1, "lighting.sudden_factor",
        "needs interval > 0 and factor >= 1");
  check(l.light_off_at >= 0 && l.light_off_at <= 1, "lighting.light_off_at", "must be in [0, 1]");
  check(l.ae_time_constant_s >= 0, "lighting.ae_time_constant_s", "must be >= 0");
  const auto& n = s.sensor;
  check(n.sensitivity > 0 && n.full_well_e > 0 && n.electrons_per_dn > 0 && n.read_noise_e >= 0,
        "sensor.sensitivity", "sensitivity, full well and electrons_per_dn must be positive");
  check(n.min_exposure_ms > 0 && n.exposure_ms >= n.min_exposure_ms &&
            n.max_exposure_ms >= n.exposure_ms,
        "sensor.exposure_ms", "needs 0 < min_exposure_ms <= exposure_ms <= max_exposure_ms");
  check(n.max_exposure_ms < 1000.0 / c.rate_hz, "sensor.max_exposure_ms",
        "must be shorter than the frame period");
  check(n.max_gain >= 1, "sensor.max_gain", "must be >= 1");
  check(n.vignetting >= 0 && n.vignetting <= 1, "sensor.vignetting", "must be in [0, 1]");
  check(n.psf_sigma_px >= 0 && n.psf_sigma_px <= 5, "sensor.psf_sigma_px", "must be in [0, 5]");
  check(n.supersample >= 1 && n.supersample <= 4, "sensor.supersample", "must be in [1, 4]");
  check(n.blur_step_px > 0 && n.max_subframes >= 1 && n.max_subframes <= 64, "sensor.max_subframes",
        "needs blur_step_px > 0 and 1 <= max_subframes <= 64");
  check(n.blur_method == "flow" || n.blur_method == "renders", "sensor.blur_method",
        "unknown blur method '" + n.blur_method + "' (flow, renders)");
  check(n.blur_render_px > 0 && n.blur_sample_px >= 0.25 && n.blur_sample_px <= 8, "sensor.blur_render_px",
        "needs blur_render_px > 0 and blur_sample_px in [0.25, 8]");
  check(n.blur_max_samples >= 1 && n.blur_max_samples <= 256, "sensor.blur_max_samples", "must be in [1, 256]");
  check(n.near_m > 0 && n.near_m < 1, "sensor.near_m", "must be in (0, 1) metres");
  const auto& sc = s.scene;
  check(sc.layout == "room" || sc.layout == "corridor", "scene.layout",
        "unknown layout '" + sc.layout + "' (room, corridor)");
  check(sc.texture == "rich" || sc.texture == "low", "scene.texture",
        "unknown texture style '" + sc.texture + "' (rich, low)");
  check(sc.length_m >= 3 && sc.width_m >= 2 && sc.height_m >= 2.2 && sc.length_m <= 100 &&
            sc.width_m <= 50 && sc.height_m <= 20,
        "scene.length_m", "room must be at least 3 x 2 x 2.2 m and at most 100 x 50 x 20 m");
  check(sc.shelves >= 0 && sc.wall_boxes >= 0 && sc.floor_boxes >= 0 && sc.doors >= 0 &&
            sc.windows >= 0 && sc.posters >= 0 && sc.ceiling_lights >= 0,
        "scene.shelves", "object counts must be >= 0");
  check(sc.clearance_m >= 0.2, "scene.clearance_m", "must be >= 0.2 m");
  check(sc.texels_per_m >= 20 && sc.texels_per_m <= 1000, "scene.texels_per_m", "must be in [20, 1000]");
  check(sc.window_light >= 0, "scene.window_light", "must be >= 0");
  const auto& o = s.output;
  check(o.groundtruth_rate_hz > 0 && o.groundtruth_rate_hz <= 10000, "output.groundtruth_rate_hz",
        "must be in (0, 10000]");
  check(o.start_ns >= 0, "output.start_ns", "must be >= 0");
  check(o.min_segment_px >= 0, "output.min_segment_px", "must be >= 0");
}

void apply_yaml(const ConfigNode& node, SequenceSpec& spec) {
  node.get("preset", spec.name);  // the preset itself is applied by load_spec()
  node.get("name", spec.name);
  node.get("seed", spec.seed);
  node.get("duration_s", spec.duration_s);
  read_camera(node.child("camera"), spec.camera);
  read_motion(node.child("motion"), spec.motion);
  read_lighting(node.child("lighting"), spec.lighting);
  read_sensor(node.child("sensor"), spec.sensor);
  read_scene(node.child("scene"), spec.scene);
  read_output(node.child("output"), spec.output);
  node.reject_unknown_keys();
}

SequenceSpec load_spec(const std::filesystem::path& file) {
  const auto node = ConfigNode::load_file(file);
  SequenceSpec spec;
  if (node.has("preset")) {
    const auto name = node.require<std::string>("preset");
    try {
      spec = preset(name);
    } catch (const InputError& e) {
      throw InputError(file, "preset", e.what());
    }
  }
  apply_yaml(node, spec);
  validate(spec, file);
  return spec;
}

std::string to_yaml(const SequenceSpec& s) {
  YAML::Emitter out;
  out.SetDoublePrecision(17);
  auto kv = [&](const char* key, const auto& value) { out << YAML::Key << key << YAML::Value << value; };
  out << YAML::BeginMap;
  kv("name", s.name);
  kv("seed", s.seed);
  kv("duration_s", s.duration_s);

  out << YAML::Key << "camera" << YAML::Value << YAML::BeginMap;
  kv("width", s.camera.width);
  kv("height", s.camera.height);
  kv("fx", s.camera.fx);
  kv("fy", s.camera.fy);
  kv("cx", s.camera.cx);
  kv("cy", s.camera.cy);
  out << YAML::Key << "distortion" << YAML::Value << YAML::Flow << s.camera.distortion;
  kv("rate_hz", s.camera.rate_hz);
  kv("stereo", s.camera.stereo);
  kv("baseline_m", s.camera.baseline_m);
  std::vector<double> T;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) T.push_back(s.camera.T_body_cam0.matrix()(r, c));
  out << YAML::Key << "T_body_cam0" << YAML::Value << YAML::Flow << T;
  out << YAML::EndMap;

  out << YAML::Key << "motion" << YAML::Value << YAML::BeginMap;
  kv("mean_speed", s.motion.mean_speed);
  kv("mean_angular_rate", s.motion.mean_angular_rate);
  kv("yaw_swing_deg", s.motion.yaw_swing_deg);
  kv("yaw_drift", s.motion.yaw_drift);
  kv("pitch_deg", s.motion.pitch_deg);
  kv("roll_deg", s.motion.roll_deg);
  kv("shake_m", s.motion.shake_m);
  kv("shake_deg", s.motion.shake_deg);
  kv("shake_hz", s.motion.shake_hz);
  out << YAML::EndMap;

  out << YAML::Key << "lighting" << YAML::Value << YAML::BeginMap;
  kv("mode", s.lighting.mode);
  kv("illumination", s.lighting.illumination);
  kv("low_light_level", s.lighting.low_light_level);
  kv("flicker_hz", s.lighting.flicker_hz);
  kv("flicker_depth", s.lighting.flicker_depth);
  kv("gradual_period_s", s.lighting.gradual_period_s);
  kv("gradual_factor", s.lighting.gradual_factor);
  kv("sudden_interval_s", s.lighting.sudden_interval_s);
  kv("sudden_factor", s.lighting.sudden_factor);
  kv("light_off_at", s.lighting.light_off_at);
  kv("ae_time_constant_s", s.lighting.ae_time_constant_s);
  out << YAML::EndMap;

  out << YAML::Key << "sensor" << YAML::Value << YAML::BeginMap;
  kv("sensitivity", s.sensor.sensitivity);
  kv("exposure_ms", s.sensor.exposure_ms);
  kv("min_exposure_ms", s.sensor.min_exposure_ms);
  kv("max_exposure_ms", s.sensor.max_exposure_ms);
  kv("max_gain", s.sensor.max_gain);
  kv("full_well_e", s.sensor.full_well_e);
  kv("electrons_per_dn", s.sensor.electrons_per_dn);
  kv("read_noise_e", s.sensor.read_noise_e);
  kv("vignetting", s.sensor.vignetting);
  kv("psf_sigma_px", s.sensor.psf_sigma_px);
  kv("supersample", s.sensor.supersample);
  kv("motion_blur", s.sensor.motion_blur);
  kv("blur_method", s.sensor.blur_method);
  kv("blur_step_px", s.sensor.blur_step_px);
  kv("blur_render_px", s.sensor.blur_render_px);
  kv("blur_sample_px", s.sensor.blur_sample_px);
  kv("blur_max_samples", s.sensor.blur_max_samples);
  kv("max_subframes", s.sensor.max_subframes);
  kv("near_m", s.sensor.near_m);
  out << YAML::EndMap;

  out << YAML::Key << "scene" << YAML::Value << YAML::BeginMap;
  kv("layout", s.scene.layout);
  kv("texture", s.scene.texture);
  kv("length_m", s.scene.length_m);
  kv("width_m", s.scene.width_m);
  kv("height_m", s.scene.height_m);
  kv("shelves", s.scene.shelves);
  kv("wall_boxes", s.scene.wall_boxes);
  kv("floor_boxes", s.scene.floor_boxes);
  kv("doors", s.scene.doors);
  kv("windows", s.scene.windows);
  kv("posters", s.scene.posters);
  kv("ceiling_lights", s.scene.ceiling_lights);
  kv("clearance_m", s.scene.clearance_m);
  kv("texels_per_m", s.scene.texels_per_m);
  kv("window_light", s.scene.window_light);
  out << YAML::EndMap;

  out << YAML::Key << "output" << YAML::Value << YAML::BeginMap;
  kv("lines", s.output.lines);
  kv("depth", s.output.depth);
  kv("groundtruth_rate_hz", s.output.groundtruth_rate_hz);
  kv("start_ns", s.output.start_ns);
  kv("min_segment_px", s.output.min_segment_px);
  out << YAML::EndMap;

  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

// ---------------------------------------------------------------- presets

MotionSpec motion_level(const std::string& level) {
  MotionSpec m;  // medium
  if (level == "easy") {
    m.mean_speed = 0.4;
    m.mean_angular_rate = 0.3;
    m.yaw_swing_deg = 25;
    m.pitch_deg = 12;
    m.roll_deg = 4;
    m.shake_m = 0;
    m.shake_deg = 0;
  } else if (level == "difficult") {
    m.mean_speed = 1.2;
    m.mean_angular_rate = 1.0;
    m.yaw_swing_deg = 50;
    m.yaw_drift = 0.3;
    m.pitch_deg = 28;
    m.roll_deg = 20;
    m.shake_m = 0.03;
    m.shake_deg = 1.5;
    m.shake_hz = 2.0;
  } else if (level != "medium") {
    throw InputError("unknown motion level '" + level + "' (easy, medium, difficult)");
  }
  return m;
}

namespace {

struct LightingVariant {
  const char* suffix;
  const char* description;
};

const LightingVariant kVariants[] = {
    {"normal", "office lighting, auto exposure settled"},
    {"lowlight", "0.5% of the light: longest exposure, highest gain, dark and noisy"},
    {"flicker", "lamps flickering at 107 Hz, beating with the 20 Hz frame rate"},
    {"gradual", "exposure sweeping slowly between 1/3 and 3x"},
    {"sudden", "exposure jumping by 2.5x every few seconds"},
    {"lightoff", "room lights switched off half-way; daylight and auto exposure remain"},
    {"lowtexture", "plain walls, floor and ceiling: lines carry the geometry"},
};

const char* kLevels[] = {"easy", "medium", "difficult"};

bool in_suite(const std::string& level, const std::string& variant) {
  if (variant == "normal" || variant == "lowlight" || variant == "flicker") return true;
  return level == "medium" && (variant == "lowtexture" || variant == "lightoff" || variant == "sudden");
}

void apply_variant(const std::string& variant, SequenceSpec& s) {
  auto& l = s.lighting;
  if (variant == "lowlight") l.mode = "low_light";
  else if (variant == "flicker") l.mode = "flicker";
  else if (variant == "gradual") l.mode = "exposure_gradual";
  else if (variant == "sudden") l.mode = "exposure_sudden";
  else if (variant == "lightoff") l.mode = "light_off";
  else if (variant == "lowtexture") {
    s.scene.texture = "low";
    s.scene.shelves = 1;
    s.scene.wall_boxes = 3;
    s.scene.floor_boxes = 1;
    s.scene.posters = 2;
    s.scene.windows = 1;
  }
}

}  // namespace

std::vector<PresetInfo> presets() {
  std::vector<PresetInfo> out;
  for (const char* level : kLevels)
    for (const auto& v : kVariants)
      out.push_back({std::string(level) + "_" + v.suffix,
                     std::string(level) + " motion, " + v.description, in_suite(level, v.suffix)});
  for (const char* level : kLevels)
    out.push_back({std::string("corridor_") + level + "_normal",
                   std::string("16 m corridor, ") + level + " motion, office lighting", false});
  return out;
}

std::vector<std::string> suite_presets() {
  std::vector<std::string> names;
  for (const auto& p : presets())
    if (p.in_suite) names.push_back(p.name);
  return names;
}

SequenceSpec preset(const std::string& name) {
  SequenceSpec s;
  s.name = name;
  std::string rest = name;
  if (rest.rfind("corridor_", 0) == 0) {
    rest = rest.substr(9);
    s.scene.layout = "corridor";
    s.scene.length_m = 16;
    s.scene.width_m = 2.4;
    s.scene.height_m = 2.7;
    s.scene.shelves = 0;
    s.scene.wall_boxes = 0;
    s.scene.floor_boxes = 0;
    s.scene.doors = 6;
    s.scene.windows = 1;
    s.scene.posters = 8;
    s.scene.ceiling_lights = 8;
    s.scene.clearance_m = 0.7;
  }
  const auto us = rest.find('_');
  bool known = false;
  if (us != std::string::npos) {
    const auto level = rest.substr(0, us), variant = rest.substr(us + 1);
    for (const char* l : kLevels)
      for (const auto& v : kVariants)
        known = known || (level == l && variant == v.suffix &&
                          (s.scene.layout == "room" || variant == "normal"));
    if (known) {
      s.motion = motion_level(level);
      apply_variant(variant, s);
      if (s.scene.layout == "corridor") s.motion.yaw_drift = 0;
    }
  }
  if (!known) {
    std::string list;
    for (const auto& p : presets()) list += (list.empty() ? "" : ", ") + p.name;
    throw InputError("unknown preset '" + name + "' (known: " + list + ")");
  }
  return s;
}

}  // namespace pllvo::synth
