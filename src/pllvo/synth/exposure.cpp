#include "pllvo/synth/exposure.h"

#include <algorithm>
#include <cmath>

#include "pllvo/synth/random.h"

namespace pllvo::synth {

namespace {

/// Exposure-gain product (ms at gain 1) that the camera's controller sets on top of the
/// auto exposure: a slow sweep or sudden jumps, as a factor over time.
class ExposureDisturbance {
 public:
  ExposureDisturbance(const LightingSpec& l, double duration, Random& rng) : l_(l) {
    if (l.mode != "exposure_sudden") return;
    const double log_f = std::log(l.sudden_factor);
    int level = 0;  // factor = f^level, level in {-1, 0, 1}
    for (double t = rng.uniform(0.5, 1.5) * l.sudden_interval_s; t < duration;
         t += rng.uniform(0.5, 1.5) * l.sudden_interval_s) {
      int next = level;
      while (next == level) next = rng.integer(-1, 1);
      level = next;
      jumps_.push_back({t, level * log_f});
    }
  }

  double log_factor(double t) const {
    if (l_.mode == "exposure_gradual")
      return std::log(l_.gradual_factor) * std::sin(2 * M_PI * t / l_.gradual_period_s);
    double value = 0;
    for (const auto& [when, v] : jumps_)
      if (t >= when) value = v;
    return value;
  }

 private:
  const LightingSpec& l_;
  std::vector<std::pair<double, double>> jumps_;
};

}  // namespace

ExposureSchedule::ExposureSchedule(const SequenceSpec& spec, double off_ratio) {
  const auto& l = spec.lighting;
  const auto& s = spec.sensor;
  Random rng(derive_seed(spec.seed, 0x6578706f73ULL));
  base_level_ = l.mode == "low_light" ? l.low_light_level : l.illumination;
  if (l.mode == "flicker") {
    flicker_depth_ = l.flicker_depth;
    flicker_hz_ = l.flicker_hz;
    flicker_phase_ = rng.uniform(0, 2 * M_PI);
  }
  if (l.mode == "light_off") off_time_ = l.light_off_at * spec.duration_s;
  const ExposureDisturbance disturbance(l, spec.duration_s, rng);

  const double min_p = s.min_exposure_ms, max_p = s.max_exposure_ms * s.max_gain;
  const double dt = 1.0 / spec.camera.rate_hz;
  const double alpha = l.ae_time_constant_s > 0 ? 1.0 - std::exp(-dt / l.ae_time_constant_s) : 1.0;
  // The auto exposure sees the mean scene brightness (not the flicker, which is too fast).
  auto seen = [&](double t) { return base_level_ * (state(t) == 1 ? std::max(off_ratio, 1e-6) : 1.0); };
  auto target = [&](double t) { return std::clamp(std::log(s.exposure_ms / seen(t)), std::log(min_p), std::log(max_p)); };

  const size_t n = spec.num_frames();
  frames_.resize(n);
  double log_p = target(0);
  for (size_t i = 0; i < n; ++i) {
    const double t = spec.frame_time(i);
    if (i > 0) log_p += alpha * (target(t) - log_p);
    const double p = std::clamp(std::exp(log_p + disturbance.log_factor(t)), min_p, max_p);
    FrameExposure& f = frames_[i];
    f.exposure_ms = std::clamp(p, s.min_exposure_ms, s.max_exposure_ms);
    f.gain = std::clamp(p / f.exposure_ms, 1.0, s.max_gain);
    f.light_level = light_level(t, f.exposure_ms * 1e-3);
  }
}

double ExposureSchedule::light_level(double t, double duration) const {
  if (flicker_depth_ <= 0) return base_level_;
  // Mean of 1 + d cos(2 pi f tau + phi) over the window: the cosine times sinc(pi f T).
  const double x = M_PI * flicker_hz_ * duration;
  const double sinc = x > 1e-9 ? std::sin(x) / x : 1.0;
  return base_level_ * (1.0 + flicker_depth_ * sinc * std::cos(2 * M_PI * flicker_hz_ * t + flicker_phase_));
}

}  // namespace pllvo::synth
