#pragma once
// Illumination over time and the camera's auto exposure, per frame. Computed once for the
// whole sequence (the auto exposure is a lag filter over past frames), so any frame can
// be rendered on its own.
#include <cstdint>
#include <limits>
#include <vector>

#include "pllvo/synth/spec.h"

namespace pllvo::synth {

struct FrameExposure {
  double exposure_ms = 0;
  double gain = 1;
  double light_level = 1;  ///< illumination factor, averaged over the exposure (flicker)
};

class ExposureSchedule {
 public:
  /// `off_ratio`: mean scene radiance with the room lights off relative to on (light_off).
  ExposureSchedule(const SequenceSpec& spec, double off_ratio);

  const FrameExposure& frame(size_t i) const { return frames_.at(i); }
  size_t size() const { return frames_.size(); }

  /// Mean illumination factor over [t - duration/2, t + duration/2] (the lamps' flicker).
  double light_level(double t, double duration) const;
  /// When the room lights go off (light_off mode), else +infinity.
  double light_off_time() const { return off_time_; }
  /// Lighting state at time t: 0 lights on, 1 off.
  int state(double t) const { return t >= off_time_ ? 1 : 0; }

 private:
  double base_level_ = 1;
  double flicker_depth_ = 0, flicker_hz_ = 0, flicker_phase_ = 0;
  double off_time_ = std::numeric_limits<double>::infinity();
  std::vector<FrameExposure> frames_;
};

}  // namespace pllvo::synth
