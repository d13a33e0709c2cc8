// Fuzz target: a GLSL or HLSL source as --reference-file reads it, its first line naming the
// function (empty: the file's only function). The compile must succeed or throw shaderfit::Error
// (constructs outside the subset, recursion, hostile nesting and inlining that grows without
// bound included), and what it makes must be well-formed (program_checks.hpp).
#include <string>

#include "fuzz_targets.hpp"
#include "program_checks.hpp"
#include "shaderfit/core/error.hpp"

namespace shaderfit::fuzz {

void shader(const std::uint8_t* data, std::size_t size) {
  const std::string_view text = as_text(data, size);
  const std::size_t newline = text.find('\n');
  shaderfit::reference::ReferenceText t;
  t.function = std::string(text.substr(0, newline));
  t.shader_source = newline == std::string_view::npos ? "" : std::string(text.substr(newline + 1));
  t.shader_path = "fuzz.glsl";
  try {
    check_program(shaderfit::reference::compile_reference(t));
  } catch (const Error&) {
    // The expected outcome for bad input.
  }
}

}  // namespace shaderfit::fuzz

SHADERFIT_FUZZ_ENTRY(shader)
