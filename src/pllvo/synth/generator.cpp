#include "pllvo/synth/generator.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "pllvo/common/error.h"
#include "pllvo/synth/layout.h"
#include "pllvo/synth/random.h"

namespace pllvo::synth {

namespace {
constexpr uint64_t kNoiseStream = 0x6e6f697365ULL;

/// One render contributing to a frame: the scene at `time` in lighting `state`, weighted.
struct ExposurePart {
  double time;
  int state;
  double weight;
};
}  // namespace

Generator::Generator(SequenceSpec spec) : spec_(std::move(spec)) {
  validate(spec_);
  scene_ = build_scene(spec_.scene, spec_.seed);
  path_ = std::make_shared<DronePath>(spec_.motion, scene_, spec_.seed);
  init();
}

Generator::Generator(SequenceSpec spec, Scene scene, std::shared_ptr<const CameraPath> path)
    : spec_(std::move(spec)), scene_(std::move(scene)), path_(std::move(path)) {
  validate(spec_);
  if (!path_) throw InternalError("synth::Generator: no camera path");
  init();
}

void Generator::init() {
  const auto& c = spec_.camera;
  const auto cam = std::make_shared<camera::PinholeRadtan>(
      c.width, c.height, camera::PinholeIntrinsics{c.fx, c.fy, c.cx, c.cy}, c.distortion);
  cameras_.push_back(cam);
  T_body_cam_.push_back(c.T_body_cam0);
  if (c.stereo) {  // a rectified pair: cam1 is cam0 moved by the baseline along its x axis
    cameras_.push_back(cam);
    T_body_cam_.push_back(c.T_body_cam0 * Eigen::Translation3d(c.baseline_m, 0, 0));
  }
  lens_ = std::make_unique<LensModel>(*cam);
  sensor_ = std::make_unique<SensorModel>(spec_.sensor, lens_->bearings());
  const double light_scale = light_normalisation(scene_);
  radiance_.push_back(bake_radiance(scene_, 0, light_scale));
  double off_ratio = 1.0;
  if (spec_.lighting.mode == "light_off") {
    radiance_.push_back(bake_radiance(scene_, 1, light_scale));
    off_ratio = radiance_[1].mean_radiance / std::max(radiance_[0].mean_radiance, 1e-12);
  }
  exposure_ = std::make_unique<ExposureSchedule>(spec_, off_ratio);
  main_ = std::make_unique<Rasterizer>(lens_->ideal_view(), spec_.sensor.near_m, true, spec_.sensor.supersample);
  scratch_ = std::make_unique<Rasterizer>(lens_->ideal_view(), spec_.sensor.near_m, true, spec_.sensor.supersample);
  flow_blur_ = std::make_unique<FlowBlur>(*lens_, spec_.sensor.blur_sample_px, spec_.sensor.blur_max_samples);
}

int64_t Generator::stamp_ns(size_t i) const { return stamp_ns(time(i)); }

int64_t Generator::stamp_ns(double t) const { return spec_.output.start_ns + std::llround(t * 1e9); }

Eigen::Isometry3d Generator::T_world_body(double t) const { return path_->pose(t) * T_body_cam_[0].inverse(); }

Eigen::Isometry3d Generator::T_world_cam(size_t c, double t) const { return T_world_body(t) * T_body_cam_.at(c); }

Eigen::Vector3d Generator::body_velocity(double t) const {
  if (T_body_cam_[0].translation().isZero(0)) return path_->velocity(t);
  constexpr double h = 1e-5;
  return (T_world_body(t + h).translation() - T_world_body(t - h).translation()) / (2 * h);
}

RenderedFrame Generator::render(size_t i, const RenderOptions& options) {
  if (i >= num_frames())
    throw InputError("synth: frame " + std::to_string(i) + " out of range (" + std::to_string(num_frames()) +
                     " frames)");
  RenderedFrame f;
  f.index = i;
  f.time_s = time(i);
  f.stamp_ns = stamp_ns(i);
  f.T_world_body = T_world_body(f.time_s);
  f.velocity_world = body_velocity(f.time_s);
  f.exposure = exposure_->frame(i);
  for (size_t c = 0; c < cameras_.size(); ++c)
    f.cameras.push_back(render_camera(c, i, f.time_s, f.exposure, options, f.subframes));
  return f;
}

double Generator::image_motion(size_t c, double t, double exposure_s) const {
  // Image motion over the exposure of a grid of visible points, using the depth just rendered.
  const IdealView& view = lens_->ideal_view();
  const Eigen::Isometry3d T_wc = T_world_cam(c, t);
  const Eigen::Isometry3d T_aw = T_world_cam(c, t - exposure_s / 2).inverse();
  const Eigen::Isometry3d T_bw = T_world_cam(c, t + exposure_s / 2).inverse();
  const cv::Mat& xy = lens_->ideal_coordinates();
  const cv::Mat& inv_depth = main_->inverse_depth();
  double motion = 0;
  for (int gy = 0; gy < 7; ++gy)
    for (int gx = 0; gx < 9; ++gx) {
      const cv::Vec2f p = xy.at<cv::Vec2f>((xy.rows - 1) * gy / 6, (xy.cols - 1) * gx / 8);
      const int xi = static_cast<int>(std::lround(p[0])), yi = static_cast<int>(std::lround(p[1]));
      const float w = inv_depth.at<float>(yi, xi);
      if (w <= 0) continue;
      const Eigen::Vector3d X_c((p[0] - view.cx) / view.fx / w, (p[1] - view.cy) / view.fy / w, 1.0 / w);
      const Eigen::Vector3d X_w = T_wc * X_c;
      const Eigen::Vector3d A = T_aw * X_w, B = T_bw * X_w;
      if (A.z() < 0.01 || B.z() < 0.01) return std::numeric_limits<double>::infinity();
      motion = std::max(motion, (view.project(A) - view.project(B)).norm());
    }
  return motion;
}

int Generator::num_renders(double motion, double step_px) const {
  const int cap = spec_.sensor.max_subframes % 2 ? spec_.sensor.max_subframes : spec_.sensor.max_subframes - 1;
  if (!(motion < cap * step_px)) return std::max(cap, 1);
  int n = static_cast<int>(std::ceil(motion / step_px));
  if (n % 2 == 0) ++n;  // odd: the middle render is the one at the timestamp
  return std::clamp(n, 1, std::max(cap, 1));
}

double Generator::expose_by_renders(size_t c, double t, double e, int state_mid, int n) {
  std::vector<ExposurePart> parts;
  const double t_off = exposure_->light_off_time();
  for (int k = 0; k < n; ++k) {
    const double tau = n == 1 ? t : t + e * ((k + 0.5) / n - 0.5);
    const double lo = tau - e / (2 * n), hi = tau + e / (2 * n);
    const double light = exposure_->light_level(tau, e / n) / n;
    if (t_off > lo && t_off < hi) {
      const double before = (t_off - lo) / (hi - lo);
      parts.push_back({tau, 0, light * before});
      parts.push_back({tau, 1, light * (1 - before)});
    } else {
      parts.push_back({tau, exposure_->state(tau), light});
    }
  }
  if (parts.size() == 1) {
    lens_->distort(main_->radiance(), distorted_);
    return parts[0].weight;
  }
  accumulated_.create(main_->radiance().size(), CV_32F);
  accumulated_.setTo(0);
  bool main_used = false;
  for (const auto& p : parts) {
    const Rasterizer* r = main_.get();
    if (main_used || p.time != t || p.state != state_mid) {
      scratch_->render(scene_, radiance_[p.state], T_world_cam(c, p.time).inverse(), 1.0f, false);
      r = scratch_.get();
    } else {
      main_used = true;
    }
    cv::scaleAdd(r->radiance(), p.weight, accumulated_, accumulated_);
  }
  lens_->distort(accumulated_, distorted_);
  return 1.0;
}

void Generator::expose_by_flow(size_t c, double t, double e, int state, int n, double motion) {
  // Each render covers 1/n of the exposure; its paths reach half of that motion either way.
  const BlurRegion& region = lens_->blur_region(0.625 * motion / n + 2);
  const Eigen::Isometry3d T_world_mid = T_world_cam(c, t);
  for (int k = 0; k < n; ++k) {
    const double tau = t + e * ((k + 0.5) / n - 0.5);
    const Rasterizer* r = main_.get();
    Eigen::Isometry3d T_world_render = T_world_mid;
    if (2 * k + 1 == n) {  // the middle one: extend the render at the timestamp by the margin
      main_->render(scene_, radiance_[state], T_world_mid.inverse(), 1.0f, false, &region.ring);
    } else {
      T_world_render = T_world_cam(c, tau);
      scratch_->render(scene_, radiance_[state], T_world_render.inverse(), 1.0f, false, &region.all);
      r = scratch_.get();
    }
    const Eigen::Isometry3d T_start = T_world_cam(c, tau - e / (2 * n)).inverse() * T_world_render;
    const Eigen::Isometry3d T_end = T_world_cam(c, tau + e / (2 * n)).inverse() * T_world_render;
    const float weight = static_cast<float>(exposure_->light_level(tau, e / n) / n);
    flow_blur_->accumulate(*r, T_start, T_end, weight, region, distorted_, k > 0);
  }
}

CameraFrame Generator::render_camera(size_t c, size_t frame, double t, const FrameExposure& exposure,
                                     const RenderOptions& options, int& subframes) {
  CameraFrame out;
  out.T_world_cam = T_world_cam(c, t);
  const Eigen::Isometry3d T_cw = out.T_world_cam.inverse();
  const double e = exposure.exposure_ms * 1e-3;
  const int state_mid = exposure_->state(t);
  const bool truth = options.lines || options.depth;
  main_->render(scene_, radiance_[state_mid], T_cw, 1.0f, truth);

  // Motion blur; the lights going off inside this exposure take sub-exposure renders.
  const auto& s = spec_.sensor;
  const double motion = s.motion_blur && e > 0 ? image_motion(c, t, e) : 0.0;
  const double t_off = exposure_->light_off_time();
  const bool switch_inside = t_off > t - e / 2 && t_off < t + e / 2;
  double light = 1.0;
  int n = 1;
  if (s.blur_method == "renders" || switch_inside) {
    n = s.motion_blur && e > 0 ? num_renders(motion, s.blur_step_px) : 1;
    light = expose_by_renders(c, t, e, state_mid, n);
  } else if (motion < 0.5 * s.blur_sample_px) {  // nothing to see
    lens_->distort(main_->radiance(), distorted_);
    light = exposure_->light_level(t, e);
  } else {
    n = num_renders(motion, s.blur_render_px);
    expose_by_flow(c, t, e, state_mid, n, motion);
  }
  subframes = std::max(subframes, n);

  sensor_->blur(distorted_);
  out.image = sensor_->record(distorted_, light, exposure.exposure_ms, exposure.gain,
                              derive_seed(spec_.seed, kNoiseStream, frame, c), options.noise);
  cv::Mat clean;
  if (options.clean || options.lines) {
    sensor_->electrons(distorted_, light, exposure.exposure_ms, electrons_);
    clean = sensor_->expected_dn(electrons_, exposure.gain);
  }
  if (options.lines) {
    SegmentOptions so;
    so.min_length_px = spec_.output.min_segment_px;
    so.near_m = spec_.sensor.near_m;
    out.segments = visible_segments(scene_, T_cw, *cameras_[c], *main_, so);
    measure_contrast(clean, out.segments);
  }
  if (options.depth) out.depth = depth_image(scene_, T_cw, *lens_, *main_);
  if (options.clean) out.clean = clean;
  return out;
}

}  // namespace pllvo::synth
