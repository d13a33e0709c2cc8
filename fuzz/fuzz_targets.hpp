// The fuzz targets: one entry function per user-facing reader, shared by the libFuzzer programs
// (built with -DSHADERFIT_FUZZ=ON, see scripts/fuzz) and by fuzz_regressions_test.cpp, which runs
// every file in fuzz/corpus/<name>/ and fuzz/regressions/<name>/ through them in the normal build.
//
// Contract of each entry: bad input is expected and ends in shaderfit::Error, which the entry
// catches. Anything else that escapes (another exception type, a sanitizer report, a crash) is a
// bug, and so is a broken round trip, which the entry reports by throwing FuzzFailure.
#pragma once

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace shaderfit::fuzz {

// A property the target checks does not hold (for example: printed formula does not read back).
class FuzzFailure : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

inline std::string_view as_text(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

// The entry functions, one per <name>_fuzz.cpp:
// formula: parse_formula, then everything `shaderfit cost` and `shaderfit codegen` do with it.
// csv: parse_csv, the numeric view of each column, and the to_csv round trip.
// options: the option parsers (--material, --ops, --domain, --grid, --define, --constraint,
//   --cond, --form, --transform), chosen by the first byte.
// front: parse_front (a search front's JSON, as `shaderfit codegen --front` reads it), then code
//   for each member.
void formula(const std::uint8_t* data, std::size_t size);
void csv(const std::uint8_t* data, std::size_t size);
void options(const std::uint8_t* data, std::size_t size);
void front(const std::uint8_t* data, std::size_t size);
// checkpoint: parse_checkpoint (`shaderfit search --resume FILE`), its write-back round trip and
//   the check against a search's data and options.
void checkpoint(const std::uint8_t* data, std::size_t size);
// reference: compile_reference on a reference formula (the lines before the last: definitions),
//   the program's checks (program_checks.hpp), and the superset of parse_formula it must be.
// shader: compile_reference on a GLSL or HLSL source whose first line names the function.
void reference(const std::uint8_t* data, std::size_t size);
void shader(const std::uint8_t* data, std::size_t size);

struct Target {
  const char* name;  // also the folder under fuzz/corpus and fuzz/regressions
  void (*run)(const std::uint8_t*, std::size_t);
};

// The targets compiled into this program, each added by its file at static initialisation (so a
// test program may hold only some of them: the sanitizer part of scripts/test does).
inline std::vector<Target>& registered_targets() {
  static std::vector<Target> targets;
  return targets;
}
struct Registration {
  Registration(const char* name, void (*run)(const std::uint8_t*, std::size_t)) {
    registered_targets().push_back({name, run});
  }
};

}  // namespace shaderfit::fuzz

// In a libFuzzer program (SHADERFIT_LIBFUZZER) the file's function is the fuzzer's entry;
// elsewhere it registers itself for fuzz_regressions_test.cpp.
#ifdef SHADERFIT_LIBFUZZER
#define SHADERFIT_FUZZ_ENTRY(name)                                                    \
  extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) { \
    shaderfit::fuzz::name(data, size);                                                \
    return 0;                                                                         \
  }
#else
#define SHADERFIT_FUZZ_ENTRY(name) \
  static const shaderfit::fuzz::Registration name##_registration(#name, shaderfit::fuzz::name);
#endif
