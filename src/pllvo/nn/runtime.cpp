#include "pllvo/nn/runtime.h"

#include <dlfcn.h>
#include <malloc.h>

#include <cstdlib>

#include <ATen/Parallel.h>
#include <spdlog/spdlog.h>

namespace pllvo::nn {

void keep_freed_memory() {
  mallopt(M_MMAP_MAX, 0);               // no mmap: every block comes from a heap...
  mallopt(M_TRIM_THRESHOLD, 1 << 30);   // ...which is not given back to the system...
  mallopt(M_TOP_PAD, 64 << 20);         // ...and grows in large steps
}

void set_num_threads(int n) {
  if (n <= 0) return;
  at::set_num_threads(n);
  // libgomp reads OMP_WAIT_POLICY when it loads, so it cannot be changed from here. With the
  // default, waiting threads spin: on a busy 2-core machine that made LightGlue ~10x slower.
  static bool warned = false;
  if (n > 1 && !warned && !std::getenv("OMP_WAIT_POLICY")) {
    warned = true;
    spdlog::info("nn: {} threads with OpenMP's default spin-waiting; on a shared or busy CPU set "
                 "OMP_WAIT_POLICY=PASSIVE before starting pllvo (docs/nn.md)", n);
  }
  // Looked up at run time: the library does not link OpenBLAS itself (executables do, see
  // cmake/PllvoDependencies.cmake), and another BLAS may serve the process.
  using SetThreads = void (*)(int);
  if (auto* f = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"))) f(n);
}

int num_threads() { return at::get_num_threads(); }

namespace {

/// libgomp's threads sleep instead of spinning when they wait (OMP_WAIT_POLICY=PASSIVE, read
/// when libgomp loads): then both pools can run at once without taking turns on the cores.
bool openmp_waits_passively() {
  const char* policy = std::getenv("OMP_WAIT_POLICY");
  return policy && (std::string(policy) == "PASSIVE" || std::string(policy) == "passive");
}

}  // namespace

MatmulThreads::MatmulThreads() : torch_threads_(openmp_waits_passively() ? 1 : at::get_num_threads()) {
  if (torch_threads_ > 1) at::set_num_threads(1);
}

MatmulThreads::~MatmulThreads() {
  if (torch_threads_ > 1) at::set_num_threads(torch_threads_);
}

std::string blas_library() {
  void* sym = dlsym(RTLD_DEFAULT, "sgemm_");
  Dl_info info{};
  if (!sym || !dladdr(sym, &info) || !info.dli_fname) return "";
  return info.dli_fname;
}

bool blas_is_openblas() {
  // Debian's OpenBLAS is libopenblas.so.0 or, through the alternatives, .../openblas-pthread/libblas.so.3.
  const auto lib = blas_library();
  return lib.find("openblas") != std::string::npos;
}

}  // namespace pllvo::nn
