#include "pllvo/nn/runtime.h"

#include <dlfcn.h>

#include <ATen/Parallel.h>

namespace pllvo::nn {

void set_num_threads(int n) {
  if (n <= 0) return;
  at::set_num_threads(n);
  // Looked up at run time: the library does not link OpenBLAS itself (executables do, see
  // cmake/PllvoDependencies.cmake), and another BLAS may serve the process.
  using SetThreads = void (*)(int);
  if (auto* f = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"))) f(n);
}

int num_threads() { return at::get_num_threads(); }

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
