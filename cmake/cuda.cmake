# The optional CUDA backend (docs/gpu.md).
#
# SHADERFIT_CUDA: AUTO (default) builds the shaderfit_cuda target when nvcc is found, ON requires
# it, OFF never builds it. nvcc is looked for in $CUDA_PATH/bin, on PATH, then in
# /usr/local/cuda/bin (where NVIDIA's packages put it, often not on PATH); CMAKE_CUDA_COMPILER or
# CUDACXX, when set, say which one to use. Without CUDA every target still builds:
# src/gpu/backend_none.cpp reports "this build has no CUDA support".
#
# Sets SHADERFIT_HAVE_CUDA (ON/OFF) for the rest of CMakeLists.txt.
set(SHADERFIT_CUDA AUTO CACHE STRING "CUDA backend: AUTO (when nvcc is found), ON or OFF")
set_property(CACHE SHADERFIT_CUDA PROPERTY STRINGS AUTO ON OFF)
# Two architectures keep the CI compile short: sm_80 (A100) as machine code, and sm_90 (H100)
# as machine code plus PTX, which newer GPUs compile at load time.
set(SHADERFIT_CUDA_ARCHITECTURES "80-real;90" CACHE STRING
    "CUDA architectures of shaderfit_cuda (CMAKE_CUDA_ARCHITECTURES syntax)")

set(SHADERFIT_HAVE_CUDA OFF)
if(NOT SHADERFIT_CUDA STREQUAL "OFF")
  if(NOT DEFINED CMAKE_CUDA_COMPILER AND NOT DEFINED ENV{CUDACXX})
    find_program(SHADERFIT_NVCC nvcc HINTS ENV CUDA_PATH PATHS /usr/local/cuda PATH_SUFFIXES bin)
    if(SHADERFIT_NVCC)
      # check_language reads CUDACXX, and still tries the compiler before saying yes.
      set(ENV{CUDACXX} "${SHADERFIT_NVCC}")
    endif()
  endif()
  include(CheckLanguage)
  check_language(CUDA)
  if(CMAKE_CUDA_COMPILER)
    if(NOT DEFINED CMAKE_CUDA_ARCHITECTURES)
      set(CMAKE_CUDA_ARCHITECTURES "${SHADERFIT_CUDA_ARCHITECTURES}")
    endif()
    enable_language(CUDA)
    set(SHADERFIT_HAVE_CUDA ON)
  elseif(SHADERFIT_CUDA STREQUAL "ON")
    message(FATAL_ERROR "SHADERFIT_CUDA=ON but no CUDA compiler (nvcc) was found")
  endif()
endif()
message(STATUS "shaderfit: CUDA backend ${SHADERFIT_HAVE_CUDA}")

if(SHADERFIT_HAVE_CUDA)
  # C++20 as the host code; CMake 3.25 does not know nvcc's flag for it (later versions do).
  if(NOT DEFINED CMAKE_CUDA20_STANDARD_COMPILE_OPTION)
    set(CMAKE_CUDA20_STANDARD_COMPILE_OPTION "-std=c++20")
    set(CMAKE_CUDA20_EXTENSION_COMPILE_OPTION "-std=c++20")
  endif()
  set(CMAKE_CUDA_STANDARD 20)
  set(CMAKE_CUDA_STANDARD_REQUIRED ON)
  set(CMAKE_CUDA_EXTENSIONS OFF)
  if(CCACHE_PROGRAM)
    set(CMAKE_CUDA_COMPILER_LAUNCHER "${CCACHE_PROGRAM}")
  endif()
  find_package(CUDAToolkit REQUIRED)
  # The kernels and their launches; they share code with the host only through header-only
  # SF_CPU_GPU code, so this target links nothing of shaderfit's.
  file(GLOB SHADERFIT_CUDA_SOURCES CONFIGURE_DEPENDS src/gpu/*.cu)
  add_library(shaderfit_cuda STATIC ${SHADERFIT_CUDA_SOURCES})
  target_include_directories(shaderfit_cuda PRIVATE include src)
  target_link_libraries(shaderfit_cuda PUBLIC CUDA::cudart_static)
  target_compile_options(shaderfit_cuda PRIVATE
    # No a*b+c contraction, as -ffp-contract=off on the host: + - * / give the CPU's bits.
    $<$<COMPILE_LANGUAGE:CUDA>:--fmad=false>
    # op.hpp's "not an operator" branch divides by zero on purpose, to make a NaN.
    $<$<COMPILE_LANGUAGE:CUDA>:-diag-suppress=39>)
  # Created before CMakeLists.txt adds its directory-wide host flags (-ffp-contract=off, the
  # sanitizers), which nvcc would not accept.
endif()
