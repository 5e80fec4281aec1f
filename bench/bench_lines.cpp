// Line front end speed on EuRoC frames (752x480), one core, side by side with OpenCV's LSD:
// detection (prefilter + EDLines + sub-pixel refit + merge), filtering (cross constraint) and
// tracking (pyramid of the new frame + line optical flow), and the three together per frame.
// The fixture's camera is at rest, so each frame's "next frame" is the frame moved by a known
// small rigid motion (0.5 deg about the centre, (3, -2) px): the tracker does real work and its
// endpoint error against that motion is printed too.
// Run: build/bin/bench_lines   (prints the ratio LSD / (detect + filter + track) at the end)
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

namespace {
using namespace pllvo::lines;

constexpr int kFrames = 20;
constexpr double kAngleDeg = 0.5, kShiftX = 3.0, kShiftY = -2.0;

struct Frames {
  std::vector<cv::Mat> now, next;
  cv::Mat motion;  // 2x3 affine from a frame to its "next"
};

const Frames& frames() {
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

std::vector<LineSegment> to_segments(const std::vector<cv::Vec4f>& v) {
  std::vector<LineSegment> out;
  for (const auto& r : v) out.emplace_back(Eigen::Vector2d(r[0], r[1]), Eigen::Vector2d(r[2], r[3]));
  return out;
}

void BM_LsdDetect(benchmark::State& state) {
  const auto& f = frames();
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

void BM_EdgeDrawingPlain(benchmark::State& state) {
  const auto& f = frames();
  size_t i = 0, lines = 0, n = 0;
  for (auto _ : state) {
    lines += detect_edlines_plain(f.now[i], EdgeDrawingConfig::opencv_defaults()).size(), ++n;
    i = (i + 1) % f.now.size();
  }
  state.counters["lines"] = static_cast<double>(lines) / n;
}

void BM_Detect(benchmark::State& state) {
  const auto& f = frames();
  LineDetector detector;
  size_t i = 0, lines = 0, n = 0;
  for (auto _ : state) {
    lines += detector.detect(f.now[i]).size(), ++n;
    i = (i + 1) % f.now.size();
  }
  state.counters["lines"] = static_cast<double>(lines) / n;
}

void BM_CrossConstraint(benchmark::State& state) {
  const auto& f = frames();
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

void BM_Track(benchmark::State& state) {
  const auto& f = frames();
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
void BM_DetectFilterTrack(benchmark::State& state) {
  const auto& f = frames();
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

BENCHMARK(BM_LsdDetect)->Unit(benchmark::kMillisecond)->Repetitions(5)->ReportAggregatesOnly(true);
BENCHMARK(BM_EdgeDrawingPlain)->Unit(benchmark::kMillisecond)->Repetitions(5)->ReportAggregatesOnly(true);
BENCHMARK(BM_Detect)->Unit(benchmark::kMillisecond)->Repetitions(5)->ReportAggregatesOnly(true);
BENCHMARK(BM_CrossConstraint)->Unit(benchmark::kMillisecond)->Repetitions(5)->ReportAggregatesOnly(true);
BENCHMARK(BM_Track)->Unit(benchmark::kMillisecond)->Repetitions(5)->ReportAggregatesOnly(true);
BENCHMARK(BM_DetectFilterTrack)->Unit(benchmark::kMillisecond)->Repetitions(5)->ReportAggregatesOnly(true);

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
  const auto& f = frames();
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
  if (t.count("BM_LsdDetect") && t.count("BM_DetectFilterTrack")) {
    const auto [lsd_real, lsd_cpu] = t.at("BM_LsdDetect");
    const auto [all_real, all_cpu] = t.at("BM_DetectFilterTrack");
    std::printf("\nLSD detection / (detection + filtering + tracking), medians of this run: "
                "%.2fx (CPU time %.2f / %.2f ms), %.2fx (wall time %.2f / %.2f ms)\n",
                lsd_cpu / all_cpu, lsd_cpu, all_cpu, lsd_real / all_real, lsd_real, all_real);
  }
  if (t.count("BM_LsdDetect") && t.count("BM_Detect")) {
    std::printf("LSD detection / our detection alone: %.2fx (CPU time)\n",
                t.at("BM_LsdDetect").second / t.at("BM_Detect").second);
  }
  print_tracking_accuracy();
  return 0;
}
