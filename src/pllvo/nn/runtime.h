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

/// The shared library that serves the Fortran BLAS symbol `sgemm_` in this process,
/// i.e. the one LibTorch's matrix products run on (found with dlsym + dladdr). On Debian a
/// binary linking Ceres may get ATLAS here, ~12x slower than OpenBLAS; see docs/nn.md.
std::string blas_library();

/// True when blas_library() is OpenBLAS.
bool blas_is_openblas();

}  // namespace pllvo::nn
