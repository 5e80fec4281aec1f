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
#include <array>
#include <regex>
#include <stdexcept>
#include <thread>
#include <vector>
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

// With 2 threads, lane 1 runs on a second thread while lane 0 runs on the caller, each with
// LibTorch's and OpenBLAS's pools at one thread; both counts come back when the lanes end.
TEST(Blas, TwoLanesRunApartWithOneThreadEachAndRestoreTheCounts) {
  using GetThreads = int (*)();
  auto* openblas_threads = reinterpret_cast<GetThreads>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
  ASSERT_NE(openblas_threads, nullptr);
  const int before = num_threads();
  set_num_threads(2);
  {
    TwoLanes lanes;
    ASSERT_EQ(lanes.threads(), 2);
    std::array<std::thread::id, 2> ids;
    std::array<int, 2> torch{}, blas{};
    for (int round = 0; round < 3; ++round) {  // the helper serves one run after another
      lanes.run([&](int lane) {
        ids[static_cast<std::size_t>(lane)] = std::this_thread::get_id();
        torch[static_cast<std::size_t>(lane)] = num_threads();
        blas[static_cast<std::size_t>(lane)] = openblas_threads();
      });
      EXPECT_EQ(ids[0], std::this_thread::get_id());
      EXPECT_NE(ids[1], ids[0]);
      EXPECT_EQ(torch, (std::array<int, 2>{1, 1}));
      EXPECT_EQ(blas, (std::array<int, 2>{1, 1}));
    }
  }
  EXPECT_EQ(num_threads(), 2);  // restored
  EXPECT_EQ(openblas_threads(), 2);
  set_num_threads(1);
  {
    TwoLanes lanes;
    EXPECT_EQ(lanes.threads(), 1);
    std::vector<int> order;
    const auto caller = std::this_thread::get_id();
    lanes.run([&](int lane) {
      EXPECT_EQ(std::this_thread::get_id(), caller);
      order.push_back(lane);
    });
    EXPECT_EQ(order, (std::vector<int>{0, 1}));
  }
  set_num_threads(before);
}

TEST(Blas, AnExceptionOnEitherLaneReachesTheCaller) {
  const int before = num_threads();
  set_num_threads(2);
  {
    TwoLanes lanes;
    for (int failing = 0; failing < 2; ++failing) {
      try {
        lanes.run([&](int lane) {
          if (lane == failing) throw std::runtime_error("lane " + std::to_string(lane));
        });
        ADD_FAILURE() << "no exception from lane " << failing;
      } catch (const std::runtime_error& e) {
        EXPECT_EQ(std::string(e.what()), "lane " + std::to_string(failing));
      }
    }
    int ran = 0;  // still usable afterwards
    lanes.run([&](int) { ++ran; });
    EXPECT_EQ(ran, 2);
  }
  set_num_threads(before);
}

}  // namespace
}  // namespace pllvo::nn
