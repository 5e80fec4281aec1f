# Finds every dependency through its CMake package; a missing one stops with the
# Debian package that provides it (scripts/setup.sh installs them all).
macro(pllvo_require pkg apt)
  find_package(${pkg} ${ARGN} QUIET)
  if(NOT ${pkg}_FOUND)
    message(FATAL_ERROR "pllvo: CMake package '${pkg}' not found. Install the Debian package "
                        "'${apt}' (or run scripts/setup.sh, which installs every dependency).")
  endif()
endmacro()

pllvo_require(Eigen3 libeigen3-dev 3.3 NO_MODULE)
pllvo_require(OpenCV "libopencv-dev libopencv-contrib-dev" 4.5
              COMPONENTS core imgproc imgcodecs highgui calib3d features2d video videoio ximgproc line_descriptor aruco)
pllvo_require(Ceres libceres-dev)
pllvo_require(yaml-cpp libyaml-cpp-dev)
pllvo_require(CLI11 libcli11-dev)
pllvo_require(spdlog libspdlog-dev)
pllvo_require(nlohmann_json nlohmann-json3-dev)
pllvo_require(Torch libtorch-dev)
# LibTorch's own targets force libtorch into every binary with --no-as-needed, which
# costs ~0.5 s of start-up per process even in binaries that never call it. pllvo_torch
# links the same libraries plainly, so only binaries that use LibTorch load it.
find_library(PLLVO_TORCH_CPU torch_cpu HINTS ${TORCH_INSTALL_PREFIX}/lib)
find_library(PLLVO_C10 c10 HINTS ${TORCH_INSTALL_PREFIX}/lib)
if(NOT PLLVO_TORCH_CPU OR NOT PLLVO_C10)
  message(FATAL_ERROR "pllvo: libtorch_cpu/libc10 not found. Install the Debian package 'libtorch-dev'.")
endif()
add_library(pllvo_torch INTERFACE)
target_include_directories(pllvo_torch SYSTEM INTERFACE ${TORCH_INCLUDE_DIRS})
target_compile_options(pllvo_torch INTERFACE ${TORCH_CXX_FLAGS})
target_link_libraries(pllvo_torch INTERFACE "${PLLVO_TORCH_CPU}" "${PLLVO_C10}")
if(PLLVO_BUILD_TESTS)
  pllvo_require(GTest "libgtest-dev libgmock-dev")
endif()
if(PLLVO_BUILD_BENCH)
  pllvo_require(benchmark libbenchmark-dev)
endif()

# LibTorch calls the Fortran BLAS symbol sgemm_. Ceres pulls ATLAS's libf77blas into
# the link, and whichever library comes first in NEEDED serves sgemm_: ATLAS is ~12x
# slower than OpenBLAS. Linking libopenblas first, without --as-needed, makes OpenBLAS win.
find_library(PLLVO_OPENBLAS NAMES libopenblas.so.0 openblas
             PATHS /usr/lib/x86_64-linux-gnu/openblas-pthread /usr/lib/x86_64-linux-gnu)
if(NOT PLLVO_OPENBLAS)
  message(FATAL_ERROR "pllvo: libopenblas not found. Install the Debian package 'libopenblas0-pthread'.")
endif()

# Link options for every executable: OpenBLAS first and always NEEDED, so it serves
# sgemm_; everything after it --as-needed, so a binary that uses no LibTorch symbol
# (most tests) does not load LibTorch at start-up (~0.5 s of CPU per process).
function(pllvo_executable_blas target)
  target_link_libraries(${target} PRIVATE "-Wl,--no-as-needed" "${PLLVO_OPENBLAS}" "-Wl,--as-needed")
endfunction()
