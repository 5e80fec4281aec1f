// Throughput of the whole odometry (threaded, as `pllvo run`) over a rendered 752x480 stereo
// sequence (easy_normal, 15 s, 301 frames at 20 Hz): frames per second and the per-module
// split, for the default pipeline (`pllvo`: pllvo's own SuperPoint + LightGlue from models/,
// networks on keyframes only, on the worker thread), SuperPoint with the official weights and
// MNN (`superpoint_official_mnn`, needs ../shared) and the ORB front end (the baseline) side by
// side in the same run.
//
//   build/bin/bench_vo                                   # renders the sequence into /tmp first
//   PLLVO_BENCH_SEQUENCE=/data/synth/easy_normal build/bin/bench_vo --benchmark_repetitions=3
//
// Counters: fps (frames / wall time, image loading from disk included), cpu_ms_per_frame
// (process CPU time, all threads, per frame: what the run costs whatever the load), tracking_ms (the
// per-frame work of the tracking thread, loading excluded), <module>_ms (mean per call) for
// klt, line_tracking, pose; kf_<module>_ms per keyframe for detect (point extraction),
// lines, match, stereo, ba; keyframes; ate_pct (ATE RMSE % of the path).
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>

#include <sys/resource.h>

#include <benchmark/benchmark.h>

#include "pllvo/common/fixtures.h"
#include "pllvo/io/sequence.h"
#include "pllvo/nn/runtime.h"
#include "pllvo/synth/sequence_writer.h"
#include "pllvo/synth/spec.h"
#include "pllvo/vo/run_sequence.h"

namespace fs = std::filesystem;
using namespace pllvo;

namespace {

const io::Sequence& sequence() {
  static const std::unique_ptr<io::Sequence> seq = [] {
    fs::path dir;
    if (const char* given = std::getenv("PLLVO_BENCH_SEQUENCE")) {
      dir = given;
    } else {
      dir = fs::temp_directory_path() / "pllvo_bench_vo_easy_normal_15s";
      if (!fs::exists(dir)) {
        synth::SequenceSpec spec = synth::preset("easy_normal");
        spec.duration_s = 15;
        spec.camera.stereo = true;
        synth::write_sequence(spec, dir);
      }
    }
    return io::open_sequence(dir);
  }();
  return *seq;
}

double process_cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

double mean_ms(const nlohmann::json& stats, const std::string& key) {
  const auto& t = stats["timing_ms"];
  return t.contains(key) ? t[key]["mean"].get<double>() : 0.0;
}

void BM_VoSequence(benchmark::State& state, const std::string& frontend) {
  vo::VoConfig config;
  config.frontend.type = frontend == "pllvo" ? "superpoint" : frontend;
  if (frontend == "superpoint") {
    // The official weights with MNN (docs/vo.md's measurement); pllvo's LightGlue in models/
    // was trained on pllvo's SuperPoint descriptors, not on these.
    config.frontend.superpoint_weights = shared_path("models/superpoint_v1.safetensors").string();
    config.mapping.matcher = "mnn";
  }
  config.run.progress_interval_s = 0;
  const io::Sequence& seq = sequence();
  vo::RunSummary s;
  double cpu_s = 0;
  for (auto _ : state) {
    const double before = process_cpu_seconds();
    s = vo::run_sequence(seq, config, vo::RunOptions{});
    cpu_s = process_cpu_seconds() - before;
  }
  // On a shared machine wall time follows the load; CPU time per frame says what the
  // pipeline costs: <= 100 ms per frame on 2 cores is 20 frames/s when the cores are free.
  state.counters["cpu_ms_per_frame"] = 1000.0 * cpu_s / static_cast<double>(s.frames);
  const auto& j = s.stats;
  state.counters["fps"] = s.frames_per_second;
  state.counters["tracked"] = static_cast<double>(s.tracked_frames);
  state.counters["keyframes"] = static_cast<double>(s.keyframes);
  state.counters["tracking_ms"] = mean_ms(j, "frame");
  state.counters["load_ms"] = mean_ms(j, "load");
  for (const char* m : {"klt", "line_tracking", "pose", "starved_wait"}) state.counters[std::string(m) + "_ms"] = mean_ms(j, m);
  for (const char* m : {"kf_detect", "kf_lines", "kf_match", "kf_stereo", "kf_ba", "kf_total"})
    state.counters[std::string(m) + "_ms"] = mean_ms(j, m);
  state.counters["starved_waits"] = j["counts"].value("starved_waits", 0.0);
  if (s.error) state.counters["ate_pct"] = s.error->percent_of_path;
}

}  // namespace

BENCHMARK_CAPTURE(BM_VoSequence, orb, std::string("orb"))->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();
BENCHMARK_CAPTURE(BM_VoSequence, pllvo, std::string("pllvo"))->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();
BENCHMARK_CAPTURE(BM_VoSequence, superpoint_official_mnn, std::string("superpoint"))
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->UseRealTime();

int main(int argc, char** argv) {
  nn::keep_freed_memory();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::AddCustomContext("sequence", "easy_normal stereo 752x480, 15 s");
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
