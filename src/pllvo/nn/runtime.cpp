#include "pllvo/nn/runtime.h"

#include <dlfcn.h>
#include <malloc.h>

#include <cstdlib>
#include <utility>

#include <ATen/Parallel.h>
#include <c10/core/InferenceMode.h>
#include <spdlog/spdlog.h>

namespace pllvo::nn {

namespace {

using GetThreads = int (*)();
using SetThreads = void (*)(int);

GetThreads openblas_get_threads() { return reinterpret_cast<GetThreads>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads")); }
SetThreads openblas_set_threads() { return reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads")); }

}  // namespace

void keep_freed_memory() {
  mallopt(M_MMAP_MAX, 0);               // no mmap: every block comes from a heap...
  mallopt(M_TRIM_THRESHOLD, 1 << 30);   // ...which is not given back to the system...
  mallopt(M_TOP_PAD, 64 << 20);         // ...and grows in large steps
}

void set_num_threads(int n) {
  if (n <= 0) return;
  at::set_num_threads(n);
  // libgomp reads OMP_WAIT_POLICY when it loads, so it cannot be changed from here. With the
  // default, waiting threads spin; LightGlue does not use OpenMP's pool at 2 threads (TwoLanes),
  // SuperPoint's convolutions do.
  static bool told = false;
  if (n > 1 && !told && !std::getenv("OMP_WAIT_POLICY")) {
    told = true;
    spdlog::debug("nn: {} threads with OpenMP's default spin-waiting; on a shared or busy CPU "
                  "OMP_WAIT_POLICY=PASSIVE may help SuperPoint (docs/nn.md)", n);
  }
  // Looked up at run time: the library does not link OpenBLAS itself (executables do, see
  // cmake/PllvoDependencies.cmake), and another BLAS may serve the process.
  if (auto set = openblas_set_threads()) set(n);
}

int num_threads() { return at::get_num_threads(); }

TwoLanes::TwoLanes() : torch_threads_(at::get_num_threads()) {
  if (torch_threads_ < 2) return;
  at::set_num_threads(1);  // each lane's operations run on its own thread only
  const auto get = openblas_get_threads();
  blas_set_threads_ = openblas_set_threads();
  if (get && blas_set_threads_) {
    blas_threads_ = get();
    blas_set_threads_(1);
  }
  helper_ = std::thread([this] { helper_loop(); });
}

TwoLanes::~TwoLanes() {
  if (!helper_.joinable()) return;
  {
    const std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  helper_.join();
  at::set_num_threads(torch_threads_);
  if (blas_threads_ > 0) blas_set_threads_(blas_threads_);
}

void TwoLanes::helper_loop() {
  const c10::InferenceMode inference;
  std::unique_lock lock(mutex_);
  for (;;) {
    wake_.wait(lock, [this] { return stop_ || job_ != nullptr; });
    if (stop_) return;
    const auto* job = std::exchange(job_, nullptr);
    lock.unlock();
    std::exception_ptr error;
    try {
      (*job)(1);
    } catch (...) {
      error = std::current_exception();
    }
    lock.lock();
    error_ = error;
    done_ = true;
    wake_.notify_all();
  }
}

void TwoLanes::run(const std::function<void(int lane)>& work) {
  if (threads() == 1) {
    work(0);
    work(1);
    return;
  }
  {
    const std::lock_guard lock(mutex_);
    job_ = &work;
    done_ = false;
    error_ = nullptr;
  }
  wake_.notify_all();
  std::exception_ptr mine;
  try {
    work(0);
  } catch (...) {
    mine = std::current_exception();
  }
  std::unique_lock lock(mutex_);
  wake_.wait(lock, [this] { return done_; });
  if (mine) std::rethrow_exception(mine);
  if (error_) std::rethrow_exception(error_);
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
