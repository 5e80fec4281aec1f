// Speed of the learned front end: SuperPoint (752x480, 376x240), LightGlue (512 and 1024
// keypoints, adaptivity off and on), mutual nearest neighbours, and the sgemm that LightGlue
// is mostly made of (OpenBLAS vs ATLAS vs LibTorch's binding). One and two threads.
// scripts/bench_nn_compare.py runs this side by side with the same networks in PyTorch
// (training/pllvo_nets) and prints the ratios; results in docs/nn.md.
//
// Each repetition is one call (Iterations(1)), after an untimed warm-up call; run with
// --benchmark_repetitions=N and read the median.
#include <benchmark/benchmark.h>
#include <dlfcn.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <map>
#include <memory>
#include <string>

#include <ATen/core/Tensor.h>
#include <ATen/ops/mm.h>
#include <ATen/ops/randn.h>
#include <c10/core/InferenceMode.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "pllvo/common/fixtures.h"
#include "pllvo/nn/lightglue.h"
#include "pllvo/nn/mnn_matcher.h"
#include "pllvo/nn/runtime.h"
#include "pllvo/nn/superpoint.h"

namespace {

using namespace pllvo;
using namespace pllvo::nn;

// Inputs shared by all benchmarks, built once. SuperPoint runs Magic Leap's weights (the
// cost of a convolution does not depend on them). The LightGlue pairs are icl250 / icl254
// (consecutive ICL-NUIM frames) with the random SuperPoint of the test vectors, top 512 or
// 1024 keypoints: the 512 pair is the LightGlue vectors' pairA input, on which the random
// LightGlue weights of setting (b) exit early and prune.
struct Inputs {
  SuperPoint superpoint{SafeTensors::load(shared_path("models/superpoint_v1.safetensors")), {}};
  cv::Mat sacre_coeur = cv::imread(shared_path("testvectors/superpoint/sacre_coeur1_752x480.png").string(), cv::IMREAD_GRAYSCALE);
  cv::Mat sacre_coeur_half;
  std::map<int, std::pair<Features, Features>> pairs;  // by keypoint count: icl250 / icl254

  Inputs() {
    cv::resize(sacre_coeur, sacre_coeur_half, {376, 240}, 0, 0, cv::INTER_AREA);
    const auto dir = shared_path("testvectors/superpoint");
    const SuperPoint random(SafeTensors::load(dir / "superpoint_random_weights.safetensors"), {});
    const cv::Mat a = cv::imread((dir / "icl250_640x480.png").string(), cv::IMREAD_GRAYSCALE);
    const cv::Mat b = cv::imread((dir / "icl254_640x480.png").string(), cv::IMREAD_GRAYSCALE);
    for (const int k : {128, 512, 1024}) pairs[k] = {random.detect(a, 0.0f, k), random.detect(b, 0.0f, k)};
  }
  static Inputs& get() {
    static Inputs inputs;
    return inputs;
  }
};

// adaptive 0: setting (a) of the test vectors (no early exit, no pruning);
// adaptive 1: setting (b) (token confidences shaped so that exit and pruning happen).
const LightGlue& lightglue(bool adaptive) {
  static std::map<bool, LightGlue> models;
  auto it = models.find(adaptive);
  if (it == models.end()) {
    const auto dir = shared_path("testvectors/lightglue");
    std::vector<std::filesystem::path> overrides;
    if (adaptive) overrides.push_back(dir / "lightglue_sp_random_l9_d256_b_token_confidence.safetensors");
    LightGlueConfig config;
    config.depth_confidence = adaptive ? 0.6f : -1.0f;
    config.width_confidence = adaptive ? 0.25f : -1.0f;
    it = models.emplace(adaptive, LightGlue(load_weights_with_overrides(dir / "lightglue_sp_random_l9_d256.safetensors", overrides), config)).first;
  }
  return it->second;
}

void BM_SuperPoint(benchmark::State& state) {
  set_num_threads(static_cast<int>(state.range(1)));
  auto& in = Inputs::get();
  const cv::Mat& image = state.range(0) == 752 ? in.sacre_coeur : in.sacre_coeur_half;
  Features f = in.superpoint.detect(image, 0.0005f, -1);  // warm-up
  for (auto _ : state) {
    f = in.superpoint.detect(image, 0.0005f, -1);
    benchmark::DoNotOptimize(f.descriptors.data());
  }
  state.counters["keypoints"] = f.size();
}
BENCHMARK(BM_SuperPoint)->ArgNames({"width", "threads"})->ArgsProduct({{752, 376}, {1, 2}})
    ->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime()->MeasureProcessCPUTime();

// The same network with each convolution layout (docs/nn.md: what helped).
void BM_SuperPointLayout(benchmark::State& state) {
  set_num_threads(1);
  static const char* names[] = {"nchw", "channels_last", "mkldnn"};
  SuperPointConfig config;
  config.conv_layout = names[state.range(0)];
  const SuperPoint net(SafeTensors::load(shared_path("models/superpoint_v1.safetensors")), config);
  const cv::Mat& image = Inputs::get().sacre_coeur;
  auto dense = net.run_network(image);
  for (auto _ : state) {
    dense = net.run_network(image);
    benchmark::DoNotOptimize(dense.scores.data());
  }
  state.SetLabel(names[state.range(0)]);
}
BENCHMARK(BM_SuperPointLayout)->ArgNames({"layout"})->DenseRange(0, 2)->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime()->MeasureProcessCPUTime();

void BM_SuperPointPostprocess(benchmark::State& state) {
  set_num_threads(static_cast<int>(state.range(0)));
  auto& in = Inputs::get();
  const auto dense = in.superpoint.run_network(in.sacre_coeur);
  for (auto _ : state) {
    const auto c = find_candidates(dense.scores, 4, 4);
    const auto f = extract_features(dense, c, select_keypoints(c, 0.0005f, -1));
    benchmark::DoNotOptimize(f.descriptors.data());
  }
}
BENCHMARK(BM_SuperPointPostprocess)->ArgNames({"threads"})->Arg(1)->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime()->MeasureProcessCPUTime();

void BM_LightGlue(benchmark::State& state) {
  set_num_threads(static_cast<int>(state.range(2)));
  const auto& [f0, f1] = Inputs::get().pairs.at(static_cast<int>(state.range(0)));
  const LightGlue& lg = lightglue(state.range(1) != 0);
  LightGlueResult r = lg.match(f0, f1);  // warm-up
  for (auto _ : state) {
    r = lg.match(f0, f1);
    benchmark::DoNotOptimize(r.matches.pairs.data());
  }
  state.counters["keypoints0"] = f0.size();
  state.counters["stop"] = r.stop;
  state.counters["matches"] = r.matches.size();
  const double pruned = ((r.prune0.array() < r.stop).count() + (r.prune1.array() < r.stop).count()) /
                        static_cast<double>(r.prune0.size() + r.prune1.size());
  state.counters["pruned_share"] = pruned;
}
BENCHMARK(BM_LightGlue)->ArgNames({"keypoints", "adaptive", "threads"})->ArgsProduct({{128, 512, 1024}, {0, 1}, {1, 2}})
    ->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime()->MeasureProcessCPUTime();

// Multiply-adds x 2 of LightGlue's full forward pass (no early exit, no pruning) with n0 and n1
// keypoints, descriptor width d and `layers` layers, counted from lightglue.cpp's products: per layer
// and image, self-attention (qkv 6nd^2, QK^T and AV 4n^2 d, out 2nd^2, FFN 2d->2d->d 12nd^2) and
// cross-attention (qk+v 4nd^2, out 2nd^2, FFN 12nd^2; each image's similarity and message 8 n0 n1 d
// for the pair: the similarity is computed once per image so that the images run apart); input and final projections 4(n0+n1)d^2 and the final similarity 2 n0 n1 d. Element-wise
// work (softmax, GELU, layer norm, rotary encoding) is left out: it is O(n d) or O(n^2) per head.
double lightglue_flops(double n0, double n1, double d, int layers) {
  const double self = 20 * (n0 + n1) * d * d + 4 * (n0 * n0 + n1 * n1) * d;
  const double cross = 18 * (n0 + n1) * d * d + 8 * n0 * n1 * d;
  return layers * (self + cross) + 4 * (n0 + n1) * d * d + 2 * n0 * n1 * d;
}

// The best of 50 products of LightGlue's commonest shape, [n, d] x [d, 3d] (the self-attention's
// qkv projection), through LibTorch at the current thread count: this machine's sgemm rate for it.
double sgemm_gflops(int n, int d) {
  c10::InferenceMode guard;
  const at::Tensor a = at::randn({n, d}), b = at::randn({d, 3 * d});
  at::Tensor c = at::mm(a, b);
  double best = 1e30;
  for (int i = 0; i < 50; ++i) {  // ~2 ms each; the best is the rate when nothing else runs
    const auto t0 = std::chrono::steady_clock::now();
    c = at::mm(a, b);
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  return 2.0 * n * d * 3 * d / best / 1e9;
}

// LightGlue's forward pass against its FLOP count and the sgemm rate measured in the same run: `limit_ms`
// is the time the products alone would take at that rate. `threads` as the pipeline sets them
// (set_num_threads; with 2, LightGlue::match runs each image's half of a layer on its own thread with
// one-thread pools, nn::TwoLanes).
void BM_LightGlueFlops(benchmark::State& state) {
  set_num_threads(static_cast<int>(state.range(1)));
  const auto& [f0, f1] = Inputs::get().pairs.at(static_cast<int>(state.range(0)));
  const LightGlue& lg = lightglue(false);
  const double rate = sgemm_gflops(static_cast<int>(f0.size()), 256);
  LightGlueResult r = lg.match(f0, f1);  // warm-up
  for (auto _ : state) {
    r = lg.match(f0, f1);
    benchmark::DoNotOptimize(r.matches.pairs.data());
  }
  const double flops = lightglue_flops(static_cast<double>(f0.size()), static_cast<double>(f1.size()), 256, 9);
  state.counters["gflop"] = flops / 1e9;
  state.counters["sgemm_gflops"] = rate;
  state.counters["limit_ms"] = 1e3 * flops / 1e9 / rate;
  state.counters["achieved_gflops"] = benchmark::Counter(flops / 1e9, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_LightGlueFlops)->ArgNames({"keypoints", "threads"})->ArgsProduct({{512, 1024}, {1, 2}})
    ->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime()->MeasureProcessCPUTime();

void BM_Mnn(benchmark::State& state) {
  set_num_threads(static_cast<int>(state.range(1)));
  const auto& [f0, f1] = Inputs::get().pairs.at(static_cast<int>(state.range(0)));
  Matches m = match_mutual_nearest(f0, f1, {});
  for (auto _ : state) {
    m = match_mutual_nearest(f0, f1, {});
    benchmark::DoNotOptimize(m.pairs.data());
  }
  state.counters["matches"] = m.size();
}
BENCHMARK(BM_Mnn)->ArgNames({"keypoints", "threads"})->ArgsProduct({{512, 1024}, {1, 2}})
    ->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime()->MeasureProcessCPUTime();

// C = A B with A 1024x512, B 512x512 (column-major Fortran sgemm_), from a given library.
using Sgemm = void (*)(const char*, const char*, const int*, const int*, const int*, const float*, const float*,
                       const int*, const float*, const int*, const float*, float*, const int*);

void run_sgemm(benchmark::State& state, Sgemm sgemm) {
  set_num_threads(static_cast<int>(state.range(0)));
  if (!sgemm) {
    state.SkipWithError("library not found");
    return;
  }
  const int m = 1024, n = 512, k = 512;
  std::vector<float> a(m * k, 0.5f), b(k * n, 0.25f), c(m * n);
  const float one = 1.0f, zero = 0.0f;
  sgemm("N", "N", &m, &n, &k, &one, a.data(), &m, b.data(), &k, &zero, c.data(), &m);
  for (auto _ : state) {
    sgemm("N", "N", &m, &n, &k, &one, a.data(), &m, b.data(), &k, &zero, c.data(), &m);
    benchmark::DoNotOptimize(c.data());
  }
}

Sgemm sgemm_from(const char* library) {
  void* handle = dlopen(library, RTLD_NOW | RTLD_NOLOAD);  // already loaded by this binary
  if (!handle) handle = dlopen(library, RTLD_NOW | RTLD_LOCAL);
  return handle ? reinterpret_cast<Sgemm>(dlsym(handle, "sgemm_")) : nullptr;
}

void BM_SgemmOpenBlas(benchmark::State& state) { run_sgemm(state, sgemm_from("libopenblas.so.0")); }
void BM_SgemmAtlas(benchmark::State& state) { run_sgemm(state, sgemm_from("libf77blas.so.3")); }
BENCHMARK(BM_SgemmOpenBlas)->ArgNames({"threads"})->Arg(1)->Arg(2)->Iterations(10)->Unit(benchmark::kMillisecond)->UseRealTime()->MeasureProcessCPUTime();
BENCHMARK(BM_SgemmAtlas)->ArgNames({"threads"})->Arg(1)->Iterations(10)->Unit(benchmark::kMillisecond)->UseRealTime()->MeasureProcessCPUTime();

// The same product through LibTorch: whichever library its sgemm_ is bound to.
void BM_SgemmTorch(benchmark::State& state) {
  set_num_threads(static_cast<int>(state.range(0)));
  c10::InferenceMode guard;
  const at::Tensor a = at::randn({1024, 512}), b = at::randn({512, 512});
  at::Tensor c = at::mm(a, b);
  for (auto _ : state) {
    c = at::mm(a, b);
    benchmark::DoNotOptimize(c.data_ptr<float>());
  }
}
BENCHMARK(BM_SgemmTorch)->ArgNames({"threads"})->Arg(1)->Arg(2)->Iterations(10)->Unit(benchmark::kMillisecond)->UseRealTime()->MeasureProcessCPUTime();

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  // PLLVO_BENCH_DEFAULT_MALLOC=1 measures without the malloc tuning (what it is worth).
  const bool tuned = !std::getenv("PLLVO_BENCH_DEFAULT_MALLOC");
  if (tuned) keep_freed_memory();
  benchmark::AddCustomContext("malloc", tuned ? "keep_freed_memory" : "glibc default");
  benchmark::AddCustomContext("sgemm_provider", blas_library());
  benchmark::AddCustomContext("torch_default_threads", std::to_string(num_threads()));
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
