#pragma once
// Process-wide settings of the inference runtime (LibTorch + the BLAS it calls).
#include <string>

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

/// For work made of matrix products (LightGlue): while it lives, LibTorch's own pool runs one
/// thread and OpenBLAS keeps the threads set_num_threads gave it, unless OpenMP's threads wait
/// passively (OMP_WAIT_POLICY=PASSIVE in the environment), when it changes nothing. Both pools at
/// 2 threads with OpenMP's default spin-waiting made LightGlue 3.6x slower than one thread on 2
/// cores (each pool's threads spin while the other's work); OpenBLAS alone at 2 threads is 1.5x
/// faster than one thread, both pools with passive waiting 1.6x (bench_nn BM_LightGlueFlops, docs/nn.md).
class MatmulThreads {
 public:
  MatmulThreads();
  ~MatmulThreads();
  MatmulThreads(const MatmulThreads&) = delete;
  MatmulThreads& operator=(const MatmulThreads&) = delete;

 private:
  int torch_threads_;
};

/// The shared library that serves the Fortran BLAS symbol `sgemm_` in this process,
/// i.e. the one LibTorch's matrix products run on (found with dlsym + dladdr). On Debian a
/// binary linking Ceres may get ATLAS here, ~12x slower than OpenBLAS; see docs/nn.md.
std::string blas_library();

/// True when blas_library() is OpenBLAS.
bool blas_is_openblas();

}  // namespace pllvo::nn
