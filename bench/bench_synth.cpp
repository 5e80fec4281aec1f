// Rendering speed of the synthetic camera on one core (the target: >= 50 frames/s at
// 752x480 for every preset of the standard suite). Run:
//   taskset -c 0 build/bin/bench_synth --benchmark_min_time=2
// items_per_second is frames per second (CPU time; stereo: pairs per second); "subframes" is
// the mean number of renders per frame for motion blur. BM_Render/<preset> runs the suite with
// the default (flow) motion blur, BM_RenderRenders/<preset> the reference method (one full
// render per sub-exposure, what every frame cost before the flow blur), BM_Stage_* the parts
// of one frame, and BM_Baseline_ImagePipeline the per-frame work that does not depend on the
// scene (lens remap + optical blur + noise + quantisation of one frame); the ratio of a
// preset's frames/s to the baseline's is what to compare between machines or runs on a
// loaded machine.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <map>
#include <string>
#include <memory>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "pllvo/synth/generator.h"

using namespace pllvo::synth;

namespace {

/// Variants of a preset: "+stereo" adds cam1, "+noblur" turns motion blur off, "+renders"
/// blurs by one full render per sub-exposure.
Generator& generator(const std::string& key) {
  static std::map<std::string, std::unique_ptr<Generator>> cache;
  auto& g = cache[key];
  if (!g) {
    SequenceSpec spec = preset(key.substr(0, key.find('+')));
    if (key.find("+stereo") != std::string::npos) spec.camera.stereo = true;
    if (key.find("+noblur") != std::string::npos) spec.sensor.motion_blur = false;
    if (key.find("+renders") != std::string::npos) spec.sensor.blur_method = "renders";
    // "+rpxN": blur_render_px = N, "+spxN": blur_sample_px = N, "+msNN": blur_max_samples = N
    // (tuning the flow blur).
    if (auto k = key.find("+rpx"); k != std::string::npos) spec.sensor.blur_render_px = std::stod(key.substr(k + 4));
    if (auto k = key.find("+spx"); k != std::string::npos) spec.sensor.blur_sample_px = std::stod(key.substr(k + 4));
    if (auto k = key.find("+msN"); k != std::string::npos) spec.sensor.blur_max_samples = std::stoi(key.substr(k + 4));
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

void BM_Render(benchmark::State& state, const std::string& name) { render_frames(state, name, {}); }

void BM_RenderWithTruth(benchmark::State& state, const std::string& name) {
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
  cv::Mat distorted;
  uint64_t seed = 1;
  for (auto _ : state) {
    gen.lens().distort(ideal, distorted);
    gen.sensor().blur(distorted);
    cv::Mat image = gen.sensor().record(distorted, 1.0, 5.0, 1.0, seed++, true);
    benchmark::DoNotOptimize(image.data);
  }
  state.SetItemsProcessed(state.iterations());
}

// Stages of one frame, to see where the time goes (medium_normal, frame 100).
void BM_Stage_Rasterize(benchmark::State& state) {
  cv::setNumThreads(1);
  Generator& gen = generator("medium_normal");
  const RadianceState radiance = bake_radiance(gen.scene(), 0, light_normalisation(gen.scene()));
  Rasterizer r(gen.lens().ideal_view(), gen.spec().sensor.near_m);
  const Eigen::Isometry3d T_cw = gen.T_world_cam(0, gen.time(100)).inverse();
  for (auto _ : state) {
    r.render(gen.scene(), radiance, T_cw, 1.0f, false);
    benchmark::DoNotOptimize(r.radiance().data);
  }
  state.SetItemsProcessed(state.iterations());
}

void BM_Stage_LensRemap(benchmark::State& state) {
  cv::setNumThreads(1);
  Generator& gen = generator("medium_normal");
  const IdealView& view = gen.lens().ideal_view();
  cv::Mat ideal(view.height, view.width, CV_32F), distorted;
  cv::randu(ideal, 0.0, 1.0);
  for (auto _ : state) {
    gen.lens().distort(ideal, distorted);
    benchmark::DoNotOptimize(distorted.data);
  }
  state.SetItemsProcessed(state.iterations());
}

void BM_Stage_OpticalBlur(benchmark::State& state) {
  cv::setNumThreads(1);
  Generator& gen = generator("medium_normal");
  cv::Mat img(gen.spec().camera.height, gen.spec().camera.width, CV_32F);
  cv::randu(img, 0.0, 1.0);
  for (auto _ : state) {
    gen.sensor().blur(img);
    benchmark::DoNotOptimize(img.data);
  }
  state.SetItemsProcessed(state.iterations());
}

void BM_Stage_Sensor(benchmark::State& state) {
  cv::setNumThreads(1);
  Generator& gen = generator("medium_normal");
  cv::Mat img(gen.spec().camera.height, gen.spec().camera.width, CV_32F);
  cv::randu(img, 0.0, 1.0);
  uint64_t seed = 1;
  for (auto _ : state) {
    cv::Mat image = gen.sensor().record(img, 1.0, 5.0, 1.0, seed++, true);
    benchmark::DoNotOptimize(image.data);
  }
  state.SetItemsProcessed(state.iterations());
}

}  // namespace

int main(int argc, char** argv) {
  auto reg = [](const std::string& bench, const std::string& key, auto fn) {
    benchmark::RegisterBenchmark((bench + "/" + key).c_str(), [fn, key](benchmark::State& st) { fn(st, key); })
        ->Unit(benchmark::kMillisecond);
  };
  benchmark::RegisterBenchmark("BM_Baseline_ImagePipeline", BM_Baseline_ImagePipeline)->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("BM_Stage_Rasterize", BM_Stage_Rasterize)->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("BM_Stage_LensRemap", BM_Stage_LensRemap)->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("BM_Stage_OpticalBlur", BM_Stage_OpticalBlur)->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("BM_Stage_Sensor", BM_Stage_Sensor)->Unit(benchmark::kMillisecond);
  for (const std::string& name : suite_presets()) reg("BM_Render", name, BM_Render);
  reg("BM_Render", "medium_normal+noblur", BM_Render);
  for (const std::string& name : {"medium_normal", "difficult_lowlight"}) reg("BM_Render", name + "+stereo", BM_Render);
  reg("BM_RenderWithTruth", "medium_normal", BM_RenderWithTruth);
  // The reference blur, side by side (the cost of every frame before the flow blur).
  for (const std::string& name : suite_presets()) reg("BM_RenderRenders", name + "+renders", BM_Render);
  if (const char* extra = std::getenv("BENCH_SYNTH_KEYS")) {  // e.g. "difficult_lowlight+rpx32+spx2,..."
    std::string keys = extra;
    for (size_t a = 0; a < keys.size();) {
      size_t b = keys.find(',', a);
      if (b == std::string::npos) b = keys.size();
      reg("BM_Render", keys.substr(a, b - a), BM_Render);
      a = b + 1;
    }
  }
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
