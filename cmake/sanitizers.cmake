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
    list(APPEND SHADERFIT_SANITIZER_FLAGS -fsanitize=float-cast-overflow
         -fno-sanitize-recover=float-cast-overflow)
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
  set_source_files_properties(${PROJECT_SOURCE_DIR}/src/search/enumeration/enum_kernels.cpp
                              PROPERTIES COMPILE_OPTIONS -mavx2)
endif()

# The part of the suite that scripts/test runs under the sanitizers on every CI run (the whole
# suite, scripts/sanitize, does not fit CI's time; docs/reliability.md): the code that reads what
# users type and give (formula parser and printer, CSV reader and data sets, the search front's
# JSON) and what it hands on to (the evaluators, the cost model, code generation, the image
# writers, the scenes), with the tests beside it and the fuzz targets' seed and regression inputs.
# It is its own library of just those areas, so that CI compiles about a fifth of the code a
# second time.
# Not registered with ctest (the full suite already runs these tests): scripts/test runs the
# program itself.
function(shaderfit_sanitized_part)
  set(areas core expr data problem eval image scene cost codegen reference)
  set(sources "")
  foreach(area ${areas})
    file(GLOB found CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/src/${area}/*.cpp)
    list(APPEND sources ${found})
  endforeach()
  # The one front-member reader and writer (search area; it needs only the areas above), which
  # the front fuzz target reads through.
  list(APPEND sources ${PROJECT_SOURCE_DIR}/src/search/front_member.cpp)
  set(tests ${sources})
  list(FILTER sources EXCLUDE REGEX "_test\\.cpp$")
  list(FILTER tests INCLUDE REGEX "_test\\.cpp$")
  list(FILTER tests EXCLUDE REGEX "umbrella_test\\.cpp$")  # includes every area
  add_library(shaderfit_part STATIC ${sources})
  target_include_directories(shaderfit_part PUBLIC ${PROJECT_SOURCE_DIR}/include
                             PRIVATE ${PROJECT_SOURCE_DIR}/src)
  target_link_libraries(shaderfit_part PUBLIC fmt::fmt Threads::Threads PRIVATE Eigen3::Eigen
                        hwy::hwy nlohmann_json::nlohmann_json OpenEXR::OpenEXR)
  shaderfit_warnings(shaderfit_part)
  set(fuzz_dir ${PROJECT_SOURCE_DIR}/fuzz)
  add_executable(shaderfit_part_tests ${tests} ${fuzz_dir}/fuzz_regressions_test.cpp
                 ${fuzz_dir}/formula_fuzz.cpp ${fuzz_dir}/csv_fuzz.cpp ${fuzz_dir}/front_fuzz.cpp
                 ${fuzz_dir}/reference_fuzz.cpp ${fuzz_dir}/shader_fuzz.cpp)
  target_include_directories(shaderfit_part_tests PRIVATE ${PROJECT_SOURCE_DIR}/src)
  target_link_libraries(shaderfit_part_tests PRIVATE shaderfit_part GTest::gtest_main
                        Eigen3::Eigen nlohmann_json::nlohmann_json)
  target_compile_definitions(shaderfit_part_tests PRIVATE
                             SHADERFIT_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
  shaderfit_warnings(shaderfit_part_tests)
endfunction()
