// Internal: how each language spells what the generated code calls, and the name checks.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "shaderfit/codegen/codegen.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/expr/op.hpp"

namespace shaderfit::codegen {

// The arithmetic of a printed function: float32, binary16 (GLSL float16_t, HLSL and Metal half,
// CUDA __half), or CUDA's __half2, two binary16 values at once.
enum class Form : std::uint8_t { Float, Half, Half2 };

// The function name for `op` in `l` and `form`; empty where the language has none (operators,
// and what spelled_out writes: GLSL's clamp(x, 0.0, 1.0), C++'s 1.0f / std::sqrt(x)).
// erf in GLSL, HLSL and Metal is the helper that code generation writes (cost/erf_helper.hpp).
// CUDA's __half spellings of the functions cuda_fp16.h has only on the device (hexp2, ...) are
// the helpers cuda_half_helpers() writes. Half forms have no asin ... erf (empty).
std::string_view call(Language l, Op op, Form form = Form::Float);

// A unary operator that `l` writes as an expression rather than a call of its name: saturate as
// GLSL's clamp(x, 0.0, 1.0), C++'s std::clamp(x, 0.0f, 1.0f) and CUDA half's __hadd_sat(x, 0);
// rsqrt as C++'s 1.0f / std::sqrt(x). `x` is the operand's text as a call argument; `level` the
// result's precedence (expr/op.hpp's levels: 4 a call, 2 a quotient). nullopt for the others.
struct SpelledOut {
  std::string text;
  int level;
};
std::optional<SpelledOut> spelled_out(Language l, Op op, Form form, const std::string& x);

// The C++ header that declares what a step of `op` calls: <algorithm> for std::clamp, else
// <cmath> (asked only for the operators written as calls).
std::string_view cpp_header(Op op);

// The value type: float, or float16_t (GLSL), half (HLSL, Metal), __half, __half2 (CUDA).
std::string_view value_type(Language l, Form form);

// A literal of `form`: float32_literal, or half_literal, or for __half2 the pair
// __float2half2_rn(0.5f) (both halves the same binary16 value).
std::string literal(double v, Language l, Form form);

// The CUDA helpers that `calls` (of a half program) need: for each function that cuda_fp16.h has
// on the device only (hsqrt, hexp2, __hfma, ...) a `__host__ __device__` sf_h... that calls it on
// the device and on the host computes in float and rounds once to binary16 (+ - * / and the
// rest of cuda_fp16.h run on the host); for sin and cos, float's __sinf and __cosf on each half
// (sf_hsin, and sf_h2sin for __half2).
std::string cuda_half_helpers(std::span<const Op> calls);
// Whether cuda_half_helpers writes a helper for `op` (Rcp: the reciprocal of a half division).
bool has_cuda_half_helper(Op op);

// Throws shaderfit::Error at `where` unless `name` is an identifier usable in every language.
void check_name(const std::string& name, std::string_view what, const SourceLocation& where);

}  // namespace shaderfit::codegen
