// Which BLAS serves LibTorch. On Debian a binary that links Ceres also gets ATLAS's
// libf77blas; if ATLAS served LibTorch's sgemm_, LightGlue would run ~12x slower.
// pllvo_executable_blas() (cmake/PllvoDependencies.cmake) links OpenBLAS first; these tests
// prove it for this executable (the CLI and benchmarks use the same CMake function).
#include <dlfcn.h>
#include <cstdlib>
#include <string>

#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <regex>
#include <sstream>

#include "nn_test_util.h"
#include "pllvo/nn/mnn_matcher.h"
#include "pllvo/nn/runtime.h"

namespace pllvo::nn {
namespace {

namespace fs = std::filesystem;

TEST(Blas, OpenBlasServesSgemm) {
  EXPECT_TRUE(blas_is_openblas()) << "sgemm_ comes from " << blas_library();
}

// A LibTorch matrix product (MNN's similarity matrix is one at::mm).
TEST(Blas, TorchMatmulRuns) {
  Features f;
  f.descriptors = DescriptorMatrix::Random(300, 256);
  f.descriptors.rowwise().normalize();
  f.keypoints = KeypointMatrix::Zero(300, 2);
  MnnConfig config;
  config.distance_threshold = 0;
  EXPECT_EQ(match_mutual_nearest(f, f, config).size(), 300);  // every point is its own mutual NN
}

// The dynamic linker's own record: run this test binary again with LD_DEBUG=bindings and
// read which library LibTorch's sgemm_ was bound to.
TEST(Blas, DynamicLinkerBindsTorchSgemmToOpenBlas) {
  const fs::path log = fs::temp_directory_path() / ("pllvo_ld_debug_" + std::to_string(::getpid()));
  const std::string self = fs::read_symlink("/proc/self/exe").string();
  std::string out;
  ASSERT_EQ(test::run_command("LD_DEBUG=bindings LD_DEBUG_OUTPUT=" + log.string() + " " + self +
                                  " --gtest_filter=Blas.TorchMatmulRuns",
                              out),
            0)
      << out;
  std::string bindings;
  for (const auto& entry : fs::directory_iterator(fs::temp_directory_path())) {
    if (entry.path().string().rfind(log.string(), 0) != 0) continue;  // LD_DEBUG_OUTPUT appends .<pid>
    std::ifstream in(entry.path());
    bindings += std::string(std::istreambuf_iterator<char>(in), {});
    fs::remove(entry.path());
  }
  const std::regex pattern(R"(binding file \S*libtorch_cpu\S* \[\d+\] to (\S+) \[\d+\]: normal symbol `sgemm_')");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(bindings, m, pattern)) << "no sgemm_ binding for libtorch_cpu in the LD_DEBUG output";
  EXPECT_NE(m[1].str().find("openblas"), std::string::npos) << "LibTorch's sgemm_ is bound to " << m[1].str();
  RecordProperty("sgemm_provider", m[1].str());
}

TEST(Blas, ThreadCountsAreSetTogether) {
  using GetThreads = int (*)();
  auto* openblas_threads = reinterpret_cast<GetThreads>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
  ASSERT_NE(openblas_threads, nullptr);
  const int before = num_threads();
  set_num_threads(2);
  EXPECT_EQ(num_threads(), 2);
  EXPECT_EQ(openblas_threads(), 2);
  set_num_threads(1);
  EXPECT_EQ(num_threads(), 1);
  EXPECT_EQ(openblas_threads(), 1);
  set_num_threads(before);
}

// LightGlue's products run on OpenBLAS's threads; LibTorch's pool stays at one thread meanwhile, unless
// OpenMP waits passively (then both pools may run: the environment of this process decides which).
TEST(Blas, MatmulThreadsLeaveTheThreadsToOpenBlasWhileTheyLive) {
  using GetThreads = int (*)();
  auto* openblas_threads = reinterpret_cast<GetThreads>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
  ASSERT_NE(openblas_threads, nullptr);
  const int before = num_threads();
  set_num_threads(2);
  const char* policy = std::getenv("OMP_WAIT_POLICY");
  const bool passive = policy && (std::string(policy) == "PASSIVE" || std::string(policy) == "passive");
  {
    const MatmulThreads matmul;
    EXPECT_EQ(num_threads(), passive ? 2 : 1);
    EXPECT_EQ(openblas_threads(), 2);
  }
  EXPECT_EQ(num_threads(), 2);  // restored
  set_num_threads(before);
}

}  // namespace
}  // namespace pllvo::nn
