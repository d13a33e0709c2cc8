// Internal: how each language spells what the generated code calls, and the name checks.
#pragma once

#include <string>
#include <string_view>

#include "shaderfit/codegen/codegen.hpp"
#include "shaderfit/core/error.hpp"

namespace shaderfit::codegen {

enum class Call : int {
  Sqrt, Rsqrt, Exp2, Log2, Exp, Log, Sin, Cos, Abs, Min, Max, Fma, Saturate,
  Asin, Acos, Atan, Atan2, Tanh, Erf,
};

// The function name for `c` in `l`; empty where the language has none (the printer spells it
// out: GLSL clamp(x, 0.0, 1.0), C++ 1.0f / std::sqrt(x) and std::clamp). erf in GLSL, HLSL and
// Metal is the helper that code generation writes (cost/erf_helper.hpp).
std::string_view call(Language l, Call c);

// Throws shaderfit::Error at `where` unless `name` is an identifier usable in every language.
void check_name(const std::string& name, std::string_view what, const SourceLocation& where);

}  // namespace shaderfit::codegen
