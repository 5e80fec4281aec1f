// pllvo lines-eval: scores the line front end on frames with ground-truth segments, side by
// side with plain EdgeDrawing and OpenCV's LSD in the same run (docs/lines.md).
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "commands.h"
#include "pllvo/common/error.h"
#include "pllvo/common/statistics.h"
#include "pllvo/features/lines/line_evaluation.h"
#include "pllvo/features/lines/lines_config.h"
#include "pllvo/features/lines/polygon_scene.h"
#include "pllvo/features/lines/synth_line_sequence.h"

namespace pllvo::cli {

namespace {
void print_score(const char* name, const lines::DetectionScore& s) {
  std::printf("  %-22s %8ld %9.1f %10.3f %8.3f %12.3f %14.3f\n", name, s.detections, s.lines_per_frame(),
              s.precision(), s.recall(), s.mean_normal_error(), s.median_endpoint_error());
}

void print_comparison(const lines::DetectorComparison& c, const lines::LinesConfig& config) {
  std::printf("  %-22s %8s %9s %10s %8s %12s %14s\n", "detector", "lines", "per_frame", "precision", "recall",
              "normal_err_px", "endpoint_err_px");
  print_score("pllvo LineDetector", c.ours);
  print_score("EdgeDrawing (OpenCV)", c.edlines);
  print_score("LSD (OpenCV)", c.lsd);
  const std::string lsd_len = "LSD >= " + std::to_string(static_cast<int>(config.detector.min_length_px)) + " px";
  print_score(lsd_len.c_str(), c.lsd_min_length);
}

// Detection and tracking scores on one `pllvo synth --lines` output folder.
void evaluate_synth_folder(const std::string& dir, const lines::LinesConfig& config,
                           const lines::DetectionScoreConfig& score, const lines::SynthFrameSelection& detection,
                           const lines::SynthFrameSelection& tracking, int chain) {
  const auto det_seq = lines::load_synth_line_sequence(dir, detection);
  long visible = 0, total = 0;
  for (const auto& f : det_seq.frames)
    for (size_t i = 0; i < f.truth.size(); ++i) {
      ++total;
      visible += f.contrast[i] >= score.min_truth_contrast;
    }
  std::printf("%s: %zu frames (every %zu from %zu); %.1f true pieces per frame, %.1f with contrast >= %.0f DN "
              "(recall counts those on edges >= %.0f px)\n",
              dir.c_str(), det_seq.frames.size(), detection.step, detection.first,
              static_cast<double>(total) / det_seq.frames.size(), static_cast<double>(visible) / det_seq.frames.size(),
              score.min_truth_contrast, score.min_truth_length_px);
  print_comparison(lines::compare_detectors(det_seq.frames, config.detector, score), config);
  if (chain < 1) return;
  const auto trk_seq = lines::load_synth_line_sequence(dir, tracking);
  const auto t =
      lines::evaluate_synth_tracking(trk_seq, config.detector, config.cross_constraint, config.tracker, chain, score);
  const auto all = t.all_endpoint_errors();
  std::printf("  tracking: %zu frames, chains of %d steps: %ld lines detected at chain starts, %ld on true edges "
              "followed; kept per frame %.3f (%.3f not counting lines leaving the image); after 1 step %.3f, after "
              "%d steps %.3f of the followed\n",
              trk_seq.frames.size(), chain, t.detected, t.started, t.kept_share_per_frame(),
              t.kept_share_per_frame_in_image(), t.kept_share(1), chain,
              t.started ? static_cast<double>(t.tracked.back()) / t.started : 0.0);
  std::printf("  endpoint error vs projected truth, median (px): at detection %.3f; tracked, all steps %.3f (%zu "
              "endpoints)",
              median(t.endpoint_errors[0]), median(all),
              all.size());
  for (int j = 1; j <= chain; j *= 2)
    std::printf(", step %d %.3f", j, median(t.endpoint_errors[j]));
  if ((chain & (chain - 1)) != 0)
    std::printf(", step %d %.3f", chain, median(t.endpoint_errors[chain]));
  std::printf("; distance to the true edge median %.3f px\n", median(t.normal_errors));
}

std::vector<std::string> split(const std::string& list) {
  std::vector<std::string> out;
  std::stringstream ss(list);
  for (std::string item; std::getline(ss, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}
}  // namespace

void add_lines_eval_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "lines-eval", "score line detection and tracking on synthetic frames with ground truth (vs EDLines and LSD)");
  struct Options {
    std::string config;
    std::string lighting = "normal,dark,noisy";
    int frames = 10;
    int tracking_frames = 20;
    std::vector<std::string> images;
    std::vector<std::string> synth;
    size_t first = 0, count = 0, step = 1;
    int chain = 10;
    double min_contrast = 10.0;
  };
  auto opt = std::make_shared<Options>();
  cmd->add_option("--config", opt->config, "lines YAML (default: built-in defaults, as config/lines.yaml)");
  cmd->add_option("--lighting", opt->lighting, "comma-separated: normal, dark, noisy")->capture_default_str();
  cmd->add_option("--frames", opt->frames, "polygon scenes per lighting for detection")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--tracking-frames", opt->tracking_frames, "frames of the tracking sequence (0: skip)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--images", opt->images,
                  "real images (no ground truth): print the prefilter decision and line counts per detector "
                  "instead of scoring the synthetic suites");
  cmd->add_option("--synth", opt->synth,
                  "`pllvo synth --lines` output folders: score detection and tracking on them instead of the "
                  "polygon scenes");
  cmd->add_option("--first", opt->first, "--synth: first frame")->capture_default_str();
  cmd->add_option("--count", opt->count, "--synth: frames scored for detection (0: all)")->capture_default_str();
  cmd->add_option("--step", opt->step, "--synth: take every step-th frame for detection")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--chain", opt->chain,
                  "--synth: tracking re-detects every `chain` frames and tracks in between (0: no tracking)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--min-contrast", opt->min_contrast,
                  "--synth: true segments with less contrast (DN, noise-free image) are not counted for recall")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->callback([opt] {
    lines::LinesConfig config;
    if (!opt->config.empty()) config = lines::load_lines_config(opt->config);
    if (!opt->images.empty()) {
      lines::LineDetector ours(config.detector);
      lines::LineDetectorConfig raw_config = config.detector;
      raw_config.prefilter.enabled = false;
      lines::LineDetector no_prefilter(raw_config);
      std::printf("%-40s %6s %7s %6s %5s %6s %13s %9s %5s %9s\n", "image", "gain", "noise", "sigma", "thr", "pllvo",
                  "no_prefilter", "EDLines", "LSD", "LSD>=min");
      for (const auto& file : opt->images) {
        const cv::Mat im = cv::imread(file, cv::IMREAD_GRAYSCALE);
        if (im.empty()) throw InputError(file, "cannot read the image");
        const auto found = ours.detect(im);
        const auto& pre = ours.last_stats().prefilter;
        const auto lsd = lines::detect_lsd(im);
        long long_lsd = 0;
        for (const auto& l : lsd) long_lsd += l.length() >= config.detector.min_length_px;
        std::printf("%-40s %6.2f %7.2f %6.2f %5d %6zu %13zu %9zu %5zu %9ld\n",
                    std::filesystem::path(file).filename().c_str(), pre.gain, pre.noise_sigma, pre.blur_sigma,
                    pre.gradient_threshold, found.size(), no_prefilter.detect(im).size(),
                    lines::detect_edlines_plain(im, lines::EdgeDrawingConfig::opencv_defaults()).size(), lsd.size(),
                    long_lsd);
      }
      return;
    }
    lines::DetectionScoreConfig score;
    score.min_truth_length_px = config.detector.min_length_px;
    if (!opt->synth.empty()) {
      score.min_truth_contrast = opt->min_contrast;
      const lines::SynthFrameSelection detection{opt->first, opt->count, opt->step};
      // Tracking needs consecutive frames: the same span, every frame.
      const size_t span = opt->count ? (opt->count - 1) * opt->step + 1 : 0;
      const lines::SynthFrameSelection tracking{opt->first, span, 1};
      for (const auto& dir : opt->synth) evaluate_synth_folder(dir, config, score, detection, tracking, opt->chain);
      return;
    }
    for (const auto& lighting : split(opt->lighting)) {
      const auto frames = lines::polygon_suite(lighting, opt->frames);
      const auto c = lines::compare_detectors(frames, config.detector, score);
      std::printf("%s lighting, %d polygon scenes 752x480 (a detection is correct when both endpoints lie within "
                  "2 px of one true segment, and so do points every 5 px between; recall = covered share of true segments "
                  ">= %.0f px)\n",
                  lighting.c_str(), opt->frames, score.min_truth_length_px);
      print_comparison(c, config);
      if (opt->tracking_frames > 1) {
        const auto seq = lines::polygon_tracking_sequence(lighting, opt->tracking_frames);
        const auto t = lines::evaluate_tracking(seq.frames, config.detector, config.cross_constraint, config.tracker,
                                                &seq.motions);
        std::printf("  tracking over %d frames (0.3 deg + (1.5, -1) px per frame, no re-detection): %d lines on "
                    "true edges, %d kept (%.1f%%); endpoint error median %.3f px; distance to the true segment "
                    "median %.3f px\n",
                    opt->tracking_frames, t.on_truth, t.kept_per_frame.back(), 100.0 * t.kept_share(),
                    median(t.endpoint_errors),
                    median(t.normal_errors));
      }
    }
  });
}

}  // namespace pllvo::cli
