# Sanitizer builds: preset `asan` (SHADERFIT_SANITIZE, scripts/sanitize) and preset `fuzz`
# (SHADERFIT_FUZZ, clang only, scripts/fuzz). Included before any target is defined, so that the
# library, the tool and the tests are all instrumented alike. docs/reliability.md says why.
option(SHADERFIT_SANITIZE "Build with AddressSanitizer and UndefinedBehaviorSanitizer" OFF)
option(SHADERFIT_FUZZ "Build the libFuzzer targets in fuzz/ (clang; implies the sanitizers)" OFF)

if(SHADERFIT_SANITIZE OR SHADERFIT_FUZZ)
  # Any undefined behaviour ends the test that hit it, instead of a line in a log nobody reads.
  set(SHADERFIT_SANITIZER_FLAGS
      -fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer)
  # Clang's `undefined` checks float-to-int conversions that overflow; GCC's needs asking.
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    list(APPEND SHADERFIT_SANITIZER_FLAGS -fsanitize=float-cast-overflow)
  endif()
  add_compile_options(${SHADERFIT_SANITIZER_FLAGS})
  add_link_options(${SHADERFIT_SANITIZER_FLAGS})
  # Bounds checks in std::vector, std::span and friends: reads past size() but within capacity
  # are invisible to AddressSanitizer.
  add_compile_definitions(_GLIBCXX_ASSERTIONS)
endif()

if(SHADERFIT_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "SHADERFIT_FUZZ needs clang (libFuzzer); use the `fuzz` preset")
  endif()
  # Coverage feedback for every object; only the fuzz programs link libFuzzer's main.
  add_compile_options(-fsanitize=fuzzer-no-link)
  # Clang 14 rejects the GCC vector helpers of the enumeration kernels (target_clones callers
  # passing 32-byte vectors to always_inline helpers: "AVX vector argument ... changes the ABI").
  # The fuzz programs never reach those kernels, so compile that one file for AVX2 here only.
  set_source_files_properties(${PROJECT_SOURCE_DIR}/src/search/enum_kernels.cpp
                              PROPERTIES COMPILE_OPTIONS -mavx2)
endif()
