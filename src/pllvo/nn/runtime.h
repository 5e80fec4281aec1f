#pragma once
// Process-wide settings of the inference runtime (LibTorch + the BLAS it calls).
#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

namespace pllvo::nn {

/// Sets LibTorch's intra-op thread count and OpenBLAS's thread count together (LightGlue
/// is mostly sgemm, run by OpenBLAS's own threads; convolutions run on LibTorch's).
/// n <= 0 keeps the current setting.
void set_num_threads(int n);

/// Tunes glibc's malloc for repeated inference, process-wide: large blocks come from the
/// heap instead of fresh mmaps, and freed memory stays in the process. The same activation
/// sizes recur every frame; by default each large one (oneDNN's and LibTorch's) is a new
/// mmap whose page faults cost SuperPoint at 752x480 about a third of its time (docs/nn.md).
/// The price: the process keeps its peak heap. Call once at start-up (the CLI and the
/// benchmarks do); without it everything still works, only slower.
void keep_freed_memory();

/// LibTorch's intra-op thread count.
int num_threads();

/// Two lanes of inference work that meet at points the caller chooses: LightGlue is the same
/// operations on each image, meeting twice a layer (cross attention), so image 1's part can run on a
/// second thread beside image 0's. With LibTorch's thread count (set_num_threads) at 2 or more, a
/// helper thread runs lane 1 while the caller runs lane 0, each with LibTorch's pool and OpenBLAS at
/// one thread (restored when this ends); otherwise the caller runs both lanes in turn. On 2 cores this
/// makes LightGlue ~1.8x faster than one thread; letting the pools split each operation gave 1.5x
/// (element-wise work left on one thread) or 3.6x slower (both pools spinning while the other works),
/// see docs/nn.md. The helper runs under c10::InferenceMode, as LightGlue::match does.
class TwoLanes {
 public:
  TwoLanes();
  ~TwoLanes();
  TwoLanes(const TwoLanes&) = delete;
  TwoLanes& operator=(const TwoLanes&) = delete;

  /// 2 when lane 1 has its own thread, else 1.
  int threads() const { return helper_.joinable() ? 2 : 1; }
  /// work(0) and work(1), in parallel when threads() is 2; returns when both are done and rethrows
  /// the first exception of either.
  void run(const std::function<void(int lane)>& work);

 private:
  void helper_loop();

  int torch_threads_ = 1;
  int blas_threads_ = 0;  // 0: OpenBLAS absent or unchanged
  void (*blas_set_threads_)(int) = nullptr;  // openblas_set_num_threads, looked up once
  std::mutex mutex_;
  std::condition_variable wake_;
  const std::function<void(int)>* job_ = nullptr;
  bool done_ = true;
  bool stop_ = false;
  std::exception_ptr error_;
  std::thread helper_;  // last: started once the state above exists
};

/// The shared library that serves the Fortran BLAS symbol `sgemm_` in this process,
/// i.e. the one LibTorch's matrix products run on (found with dlsym + dladdr). On Debian a
/// binary linking Ceres may get ATLAS here, ~12x slower than OpenBLAS; see docs/nn.md.
std::string blas_library();

/// True when blas_library() is OpenBLAS.
bool blas_is_openblas();

}  // namespace pllvo::nn
