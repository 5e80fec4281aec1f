#pragma once
// Process-wide settings of the inference runtime (LibTorch + the BLAS it calls).
#include <string>

namespace pllvo::nn {

/// Sets LibTorch's intra-op thread count and OpenBLAS's thread count together (LightGlue
/// is mostly sgemm, run by OpenBLAS's own threads; convolutions run on LibTorch's).
/// n <= 0 keeps the current setting.
void set_num_threads(int n);

/// LibTorch's intra-op thread count.
int num_threads();

/// The shared library that serves the Fortran BLAS symbol `sgemm_` in this process,
/// i.e. the one LibTorch's matrix products run on (found with dlsym + dladdr). On Debian a
/// binary linking Ceres may get ATLAS here, ~12x slower than OpenBLAS; see docs/nn.md.
std::string blas_library();

/// True when blas_library() is OpenBLAS.
bool blas_is_openblas();

}  // namespace pllvo::nn
