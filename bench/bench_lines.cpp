// Line front end speed on 752x480 frames, one core, side by side with OpenCV's LSD on the same
// frames: detection (prefilter + EDLines + sub-pixel refit + merge), filtering (cross
// constraint) and tracking (pyramid of the new frame + line optical flow), and the three
// together per frame. Two frame sets:
//  - synth: 20 pairs of consecutive frames of pllvo's synthetic `medium_normal` sequence,
//    rendered at start-up: the 20 frames with most lines among frames 0, 5, ..., 595, each with
//    its real next frame (camera motion, perspective, noise).
//  - euroc: 20 EuRoC V1_01 frames; the fixture's camera is at rest, so each frame's "next frame"
//    is the frame moved by a known small rigid motion (0.5 deg about the centre, (3, -2) px): the
//    tracker does real work and its endpoint error against that motion is printed too.
// Run: taskset -c 0 build/bin/bench_lines   (prints the ratios LSD / (detect + filter + track))
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "pllvo/common/fixtures.h"
#include "pllvo/features/lines/cross_constraint.h"
#include "pllvo/features/lines/line_detector.h"
#include "pllvo/features/lines/line_tracker.h"
#include "pllvo/synth/generator.h"

namespace {
using namespace pllvo::lines;

constexpr size_t kFrames = 20;
constexpr double kAngleDeg = 0.5, kShiftX = 3.0, kShiftY = -2.0;

struct Frames {
  std::vector<cv::Mat> now, next;
  cv::Mat motion;  // 2x3 affine from a frame to its "next"
};

const Frames& euroc_frames() {
  static const Frames f = [] {
    Frames out;
    const auto dir = pllvo::shared_path("data/euroc_V1_01_easy_micro/mav0/cam0/data");
    std::vector<std::filesystem::path> files;
    for (const auto& e : std::filesystem::directory_iterator(dir))
      if (e.path().extension() == ".png") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    files.resize(std::min<size_t>(files.size(), kFrames));
    for (const auto& p : files) {
      cv::Mat im = cv::imread(p.string(), cv::IMREAD_GRAYSCALE);
      out.motion = cv::getRotationMatrix2D(cv::Point2f(im.cols / 2.f, im.rows / 2.f), kAngleDeg, 1.0);
      out.motion.at<double>(0, 2) += kShiftX;
      out.motion.at<double>(1, 2) += kShiftY;
      cv::Mat moved;
      cv::warpAffine(im, moved, out.motion, im.size(), cv::INTER_LINEAR, cv::BORDER_REFLECT);
      out.now.push_back(im);
      out.next.push_back(moved);
    }
    return out;
  }();
  return f;
}

// The load: frames with 100+ lines. Of 120 candidate frames (every 5th of the 30 s
// sequence), the 20 where our detector finds the most lines, each with its real next frame.
const Frames& synth_frames() {
  static const Frames f = [] {
    Frames out;
    pllvo::synth::Generator gen(pllvo::synth::preset("medium_normal"));
    LineDetector detector;
    std::vector<std::pair<size_t, size_t>> count_frame;  // (lines, frame), most lines first
    for (size_t k = 0; k < 6 * kFrames; ++k) {
      const size_t i = 5 * k;
      count_frame.emplace_back(detector.detect(gen.render(i).cameras[0].image).size(), i);
    }
    std::stable_sort(count_frame.begin(), count_frame.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    count_frame.resize(kFrames);
    std::sort(count_frame.begin(), count_frame.end(), [](const auto& a, const auto& b) { return a.second < b.second; });
    for (const auto& [lines, i] : count_frame) {
      out.now.push_back(gen.render(i).cameras[0].image.clone());
      out.next.push_back(gen.render(i + 1).cameras[0].image.clone());
    }
    return out;
  }();
  return f;
}

using FrameSource = const Frames& (*)();

std::vector<LineSegment> to_segments(const std::vector<cv::Vec4f>& v) {
  std::vector<LineSegment> out;
  for (const auto& r : v) out.emplace_back(Eigen::Vector2d(r[0], r[1]), Eigen::Vector2d(r[2], r[3]));
  return out;
}

void BM_LsdDetect(benchmark::State& state, FrameSource source) {
  const auto& f = source();
  auto lsd = cv::createLineSegmentDetector();
  size_t i = 0, lines = 0, n = 0;
  for (auto _ : state) {
    std::vector<cv::Vec4f> out;
    lsd->detect(f.now[i], out);
    lines += out.size(), ++n;
    i = (i + 1) % f.now.size();
  }
  state.counters["lines"] = static_cast<double>(lines) / n;
}

void BM_EdgeDrawingPlain(benchmark::State& state, FrameSource source) {
  const auto& f = source();
  size_t i = 0, lines = 0, n = 0;
  for (auto _ : state) {
    lines += detect_edlines_plain(f.now[i], EdgeDrawingConfig::opencv_defaults()).size(), ++n;
    i = (i + 1) % f.now.size();
  }
  state.counters["lines"] = static_cast<double>(lines) / n;
}

void BM_Detect(benchmark::State& state, FrameSource source) {
  const auto& f = source();
  LineDetector detector;
  size_t i = 0, lines = 0, n = 0;
  for (auto _ : state) {
    lines += detector.detect(f.now[i]).size(), ++n;
    i = (i + 1) % f.now.size();
  }
  state.counters["lines"] = static_cast<double>(lines) / n;
}

void BM_CrossConstraint(benchmark::State& state, FrameSource source) {
  const auto& f = source();
  LineDetector detector;
  std::vector<std::vector<LineSegment>> detected;
  for (const auto& im : f.now) detected.push_back(detector.detect(im));
  size_t i = 0, kept = 0, n = 0;
  for (auto _ : state) {
    kept += apply_cross_constraint(detected[i], {}).size(), ++n;
    i = (i + 1) % detected.size();
  }
  state.counters["kept"] = static_cast<double>(kept) / n;
}

void BM_Track(benchmark::State& state, FrameSource source) {
  const auto& f = source();
  LineDetector detector;
  LineTracker tracker;
  std::vector<std::vector<LineSegment>> lines;
  std::vector<OpticalFlowPyramid> prev;
  for (const auto& im : f.now) {
    lines.push_back(apply_cross_constraint(detector.detect(im), {}));
    prev.push_back(tracker.make_pyramid(im));
  }
  size_t i = 0, in = 0, out = 0, n = 0;
  for (auto _ : state) {
    const OpticalFlowPyramid next = tracker.make_pyramid(f.next[i]);  // once per frame
    const auto tracks = tracker.track(prev[i], next, lines[i]);
    in += lines[i].size(), out += tracked_lines(tracks).size(), ++n;
    i = (i + 1) % f.now.size();
  }
  state.counters["lines"] = static_cast<double>(in) / n;
  state.counters["tracked"] = static_cast<double>(out) / n;
}

// Per frame: detect, filter, build the new frame's pyramid, track into it.
void BM_DetectFilterTrack(benchmark::State& state, FrameSource source) {
  const auto& f = source();
  LineDetector detector;
  LineTracker tracker;
  std::vector<OpticalFlowPyramid> prev;
  for (const auto& im : f.now) prev.push_back(tracker.make_pyramid(im));
  size_t i = 0, in = 0, out = 0, n = 0;
  for (auto _ : state) {
    const auto lines = apply_cross_constraint(detector.detect(f.now[i]), {});
    const OpticalFlowPyramid next = tracker.make_pyramid(f.next[i]);
    const auto tracks = tracker.track(prev[i], next, lines);
    in += lines.size(), out += tracked_lines(tracks).size(), ++n;
    i = (i + 1) % f.now.size();
  }
  state.counters["lines"] = static_cast<double>(in) / n;
  state.counters["tracked"] = static_cast<double>(out) / n;
}

BENCHMARK_CAPTURE(BM_LsdDetect, synth, &synth_frames)->Unit(benchmark::kMillisecond)->Repetitions(5)->ReportAggregatesOnly(true);
BENCHMARK_CAPTURE(BM_EdgeDrawingPlain, synth, &synth_frames)->Unit(benchmark::kMillisecond)->Repetitions(5)->ReportAggregatesOnly(true);
BENCHMARK_CAPTURE(BM_Detect, synth, &synth_frames)->Unit(benchmark::kMillisecond)->Repetitions(5)->ReportAggregatesOnly(true);
BENCHMARK_CAPTURE(BM_CrossConstraint, synth, &synth_frames)->Unit(benchmark::kMillisecond)->Repetitions(5)->ReportAggregatesOnly(true);
BENCHMARK_CAPTURE(BM_Track, synth, &synth_frames)->Unit(benchmark::kMillisecond)->Repetitions(5)->ReportAggregatesOnly(true);
BENCHMARK_CAPTURE(BM_DetectFilterTrack, synth, &synth_frames)->Unit(benchmark::kMillisecond)->Repetitions(5)->ReportAggregatesOnly(true);
BENCHMARK_CAPTURE(BM_LsdDetect, euroc, &euroc_frames)->Unit(benchmark::kMillisecond)->Repetitions(5)->ReportAggregatesOnly(true);
BENCHMARK_CAPTURE(BM_EdgeDrawingPlain, euroc, &euroc_frames)->Unit(benchmark::kMillisecond)->Repetitions(5)->ReportAggregatesOnly(true);
BENCHMARK_CAPTURE(BM_Detect, euroc, &euroc_frames)->Unit(benchmark::kMillisecond)->Repetitions(5)->ReportAggregatesOnly(true);
BENCHMARK_CAPTURE(BM_CrossConstraint, euroc, &euroc_frames)->Unit(benchmark::kMillisecond)->Repetitions(5)->ReportAggregatesOnly(true);
BENCHMARK_CAPTURE(BM_Track, euroc, &euroc_frames)->Unit(benchmark::kMillisecond)->Repetitions(5)->ReportAggregatesOnly(true);
BENCHMARK_CAPTURE(BM_DetectFilterTrack, euroc, &euroc_frames)->Unit(benchmark::kMillisecond)->Repetitions(5)->ReportAggregatesOnly(true);

// Remembers the median times so main() can print the ratios measured in this run.
class RatioReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    ConsoleReporter::ReportRuns(runs);
    for (const auto& r : runs)
      if (r.run_type == Run::RT_Aggregate && r.aggregate_name == "median")
        times[r.run_name.function_name] = {r.GetAdjustedRealTime(), r.GetAdjustedCPUTime()};
  }
  std::map<std::string, std::pair<double, double>> times;  // ms: real, cpu
};

// Endpoint error of the tracked lines against the known motion (accuracy next to the speed).
void print_tracking_accuracy() {
  const auto& f = euroc_frames();
  LineDetector detector;
  LineTracker tracker;
  const cv::Mat& M = f.motion;
  auto move = [&](const Eigen::Vector2d& p) {
    return Eigen::Vector2d(M.at<double>(0, 0) * p.x() + M.at<double>(0, 1) * p.y() + M.at<double>(0, 2),
                           M.at<double>(1, 0) * p.x() + M.at<double>(1, 1) * p.y() + M.at<double>(1, 2));
  };
  std::vector<double> err;
  size_t total = 0, kept = 0;
  for (size_t i = 0; i < f.now.size(); ++i) {
    const auto lines = apply_cross_constraint(detector.detect(f.now[i]), {});
    const auto tracks = tracker.track(tracker.make_pyramid(f.now[i]), tracker.make_pyramid(f.next[i]), lines);
    total += lines.size();
    for (size_t k = 0; k < lines.size(); ++k) {
      if (tracks[k].status != TrackStatus::Tracked) continue;
      ++kept;
      if (tracks[k].clipped) continue;  // endpoints cut at the border: not comparable
      err.push_back((tracks[k].line.start - move(lines[k].start)).norm());
      err.push_back((tracks[k].line.end - move(lines[k].end)).norm());
    }
  }
  std::sort(err.begin(), err.end());
  if (err.empty()) return;
  std::printf("tracking on %zu frames: %zu of %zu lines kept (%.1f%%), endpoint error (lines not "
              "clipped at the border) median %.3f px, 90%% %.3f px\n",
              f.now.size(), kept, total, 100.0 * kept / total, err[err.size() / 2], err[err.size() * 9 / 10]);
}
}  // namespace

int main(int argc, char** argv) {
  cv::setNumThreads(1);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  RatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  benchmark::Shutdown();
  const auto& t = reporter.times;
  for (const std::string set : {"synth", "euroc"}) {
    const std::string lsd = "BM_LsdDetect/" + set, all = "BM_DetectFilterTrack/" + set, det = "BM_Detect/" + set;
    if (t.count(lsd) && t.count(all)) {
      const auto [lsd_real, lsd_cpu] = t.at(lsd);
      const auto [all_real, all_cpu] = t.at(all);
      std::printf("\n%s: LSD detection / (detection + filtering + tracking), medians of this run: "
                  "%.2fx (CPU time %.2f / %.2f ms), %.2fx (wall time %.2f / %.2f ms)\n",
                  set.c_str(), lsd_cpu / all_cpu, lsd_cpu, all_cpu, lsd_real / all_real, lsd_real, all_real);
    }
    if (t.count(lsd) && t.count(det))
      std::printf("%s: LSD detection / our detection alone: %.2fx (CPU time)\n", set.c_str(),
                  t.at(lsd).second / t.at(det).second);
  }
  if (t.count("BM_Track/euroc")) print_tracking_accuracy();
  return 0;
}
