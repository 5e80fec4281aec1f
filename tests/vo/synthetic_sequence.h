#pragma once
// Helpers of the end-to-end VO tests: the deterministic single-thread configuration; small
// synthetic sequences (a suite preset at half the EuRoC resolution: 376 x 240, ideal pinhole, no
// motion blur, a few seconds long, so that rendering stays cheap; each rendered once per test
// program into the temp folder); a sequence with blacked-out frames; stats.json counts.
#include <filesystem>
#include <map>
#include <memory>
#include <string>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "pllvo/io/sequence.h"
#include "pllvo/synth/sequence_writer.h"
#include "pllvo/synth/spec.h"
#include "pllvo/vo/vo_config.h"

namespace pllvo::vo::testing {

/// The default pipeline in the deterministic single-thread mode, without progress lines, with
/// the ORB front end: it needs no weights and is cheap on CI's two cores, and these tests'
/// bounds were measured with it (SuperPoint: SuperPointFrontend.*, PipelineSwitches.*).
inline VoConfig deterministic() {
  VoConfig c;
  c.frontend.type = "orb";
  c.run.threaded = false;
  c.run.progress_interval_s = 0;
  return c;
}

/// The default pipeline (SuperPoint + LightGlue with the repository's weights) in the
/// deterministic single-thread mode, without progress lines: the real-fixture tests' setting.
inline VoConfig default_single_thread() {
  VoConfig c;
  c.frontend.superpoint_weights = PLLVO_SOURCE_DIR "/models/pllvo_superpoint_v1.safetensors";
  c.mapping.lightglue_weights = PLLVO_SOURCE_DIR "/models/pllvo_lightglue_v1.safetensors";
  c.run.threaded = false;
  c.run.progress_interval_s = 0;
  return c;
}

/// A count of stats.json's "counts" (0 when the run never counted it).
inline long long stats_count(const nlohmann::json& stats, const std::string& name) {
  return stats["counts"].contains(name) ? stats["counts"][name].get<long long>() : 0;
}

inline synth::SequenceSpec small_spec(const std::string& preset, double duration_s, bool stereo) {
  synth::SequenceSpec spec = synth::preset(preset);
  spec.duration_s = duration_s;
  spec.camera.width = 376;
  spec.camera.height = 240;
  spec.camera.fx /= 2, spec.camera.fy /= 2, spec.camera.cx /= 2, spec.camera.cy /= 2;
  spec.camera.distortion.clear();
  spec.camera.stereo = stereo;
  spec.sensor.motion_blur = false;
  return spec;
}

/// Renders `spec` (once per process and tag) and returns its folder.
inline std::filesystem::path rendered(const synth::SequenceSpec& spec, const std::string& tag) {
  static std::map<std::string, std::filesystem::path> cache;
  auto it = cache.find(tag);
  if (it != cache.end()) return it->second;
  const auto dir = std::filesystem::temp_directory_path() /
                   ("pllvo_vo_test_" + tag + "_" + std::to_string(::getpid()));
  synth::WriteOptions options;
  options.overwrite = true;
  synth::write_sequence(spec, dir, options);
  cache[tag] = dir;
  return dir;
}

/// Another sequence's frames, calibration, timestamps and ground truth, for wrappers that
/// change what frame() returns.
class WrappedSequence : public io::Sequence {
 public:
  explicit WrappedSequence(std::unique_ptr<io::Sequence> inner)
      : io::Sequence(inner->root()), inner_(std::move(inner)) {
    calib_ = inner_->calibration();
    stamps_ = inner_->timestamps();
    ground_truth_ = inner_->ground_truth();
  }
  std::string format() const override { return inner_->format(); }
  io::Frame frame(size_t i) const override { return inner_->frame(i); }

 private:
  std::unique_ptr<io::Sequence> inner_;
};

/// A sequence whose frames [first, last] are black (a covered lens, a light switched off).
class BlackedOutSequence : public WrappedSequence {
 public:
  BlackedOutSequence(std::unique_ptr<io::Sequence> inner, size_t first, size_t last)
      : WrappedSequence(std::move(inner)), first_(first), last_(last) {}
  io::Frame frame(size_t i) const override {
    io::Frame f = WrappedSequence::frame(i);
    if (i >= first_ && i <= last_) {
      f.left.setTo(0);
      if (!f.right.empty()) f.right.setTo(0);
    }
    return f;
  }

 private:
  size_t first_, last_;
};

/// A sequence that skips `count` frames after frame `first` (a camera driver that dropped
/// them): frame `first` shows what the inner frame `first + count` showed, at its time.
class FrameDroppingSequence : public WrappedSequence {
 public:
  FrameDroppingSequence(std::unique_ptr<io::Sequence> inner, size_t first, size_t count)
      : WrappedSequence(std::move(inner)), first_(first), count_(count) {
    stamps_.erase(stamps_.begin() + static_cast<std::ptrdiff_t>(first),
                  stamps_.begin() + static_cast<std::ptrdiff_t>(first + count));
  }
  io::Frame frame(size_t i) const override {
    io::Frame f = WrappedSequence::frame(i < first_ ? i : i + count_);
    f.index = i;
    return f;
  }

 private:
  size_t first_, count_;
};

}  // namespace pllvo::vo::testing
