// Rendering speed of the synthetic camera on one core (the target: >= 50 frames/s at
// 752x480 for a normal preset). Run:  build/bin/bench_synth
// items_per_second is frames per second (CPU time); "subframes" is the mean number of renders
// averaged per frame for motion blur. BM_Baseline_ImagePipeline is the per-frame work that
// does not depend on the scene (lens remap + optical blur + noise + quantisation of one
// frame); the ratio of a preset's frames/s to the baseline's is what to compare between
// machines or runs on a loaded machine.
#include <benchmark/benchmark.h>

#include <map>
#include <memory>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "pllvo/synth/generator.h"

using namespace pllvo::synth;

namespace {

/// Variants of a preset: "+stereo" adds cam1, "+noblur" turns motion blur off.
Generator& generator(const std::string& key) {
  static std::map<std::string, std::unique_ptr<Generator>> cache;
  auto& g = cache[key];
  if (!g) {
    SequenceSpec spec = preset(key.substr(0, key.find('+')));
    if (key.find("+stereo") != std::string::npos) spec.camera.stereo = true;
    if (key.find("+noblur") != std::string::npos) spec.sensor.motion_blur = false;
    g = std::make_unique<Generator>(spec);
  }
  return *g;
}

void render_frames(benchmark::State& state, const std::string& name, const RenderOptions& options) {
  cv::setNumThreads(1);  // one core
  Generator& gen = generator(name);
  size_t i = 0;
  int subframes = 0;
  for (auto _ : state) {
    const RenderedFrame f = gen.render(i, options);
    benchmark::DoNotOptimize(f.cameras[0].image.data);
    subframes += f.subframes;
    i = (i + 7) % gen.num_frames();  // spread over the whole flight
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["subframes"] = benchmark::Counter(subframes, benchmark::Counter::kAvgIterations);
}

void BM_Render(benchmark::State& state, std::string name) { render_frames(state, name, {}); }

void BM_RenderWithTruth(benchmark::State& state, std::string name) {
  RenderOptions o;
  o.lines = true;
  o.depth = true;
  render_frames(state, name, o);
}

void BM_Baseline_ImagePipeline(benchmark::State& state) {
  cv::setNumThreads(1);
  Generator& gen = generator("medium_normal");
  const IdealView& view = gen.lens().ideal_view();
  cv::Mat ideal(view.height, view.width, CV_32F);
  cv::randu(ideal, 0.0, 1.0);
  cv::Mat distorted, electrons;
  uint64_t seed = 1;
  for (auto _ : state) {
    gen.lens().distort(ideal, distorted);
    gen.sensor().blur(distorted);
    gen.sensor().electrons(distorted, 1.0, 5.0, electrons);
    cv::Mat image = gen.sensor().record(electrons, 1.0, seed++, true);
    benchmark::DoNotOptimize(image.data);
  }
  state.SetItemsProcessed(state.iterations());
}

}  // namespace

BENCHMARK(BM_Baseline_ImagePipeline)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Render, easy_normal, std::string("easy_normal"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Render, medium_normal, std::string("medium_normal"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Render, difficult_normal, std::string("difficult_normal"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Render, medium_lowtexture, std::string("medium_lowtexture"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Render, medium_lowlight, std::string("medium_lowlight"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Render, difficult_lowlight, std::string("difficult_lowlight"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_RenderWithTruth, medium_normal, std::string("medium_normal"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Render, medium_normal_noblur, std::string("medium_normal+noblur"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Render, medium_normal_stereo, std::string("medium_normal+stereo"))->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
