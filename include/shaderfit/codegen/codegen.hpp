// Code generation: a formula as one function in GLSL, HLSL, CUDA, C++ or Metal.
//
//   Expression e = parse_formula("r0 + (1 - cos_theta - r0) * (1 - cos_theta)^4");
//   CodegenOptions o;
//   o.language = Language::Cuda;
//   o.name = "fresnel";
//   std::cout << generate_function(e, o);
//   // __device__ __forceinline__ float fresnel(float r0, float cos_theta) {
//   //   const float t0 = 1.0f - cos_theta;
//   //   const float t1 = t0 * t0;
//   //   return fmaf(t0 - r0, t1 * t1, r0);
//   // }
//
// generate_source makes a whole file of such functions that compiles on its own (with the
// includes or the #version line its functions need); `shaderfit codegen` prints that.
//
// The function is printed from the same program the cost model counts (docs/codegen.md):
// values used more than once are named temporaries (t0, t1, ...), integer powers are the
// squaring chain the model assumed, and the evaluation order (operand order and association)
// is the model's. CUDA, C++ and Metal write fma(a, b, c) wherever the model fused a*b + c (the
// `sass` and `ptx` targets); GLSL and HLSL write a * b + c, which their compilers contract, and
// which the `generic` target counts as two operations. Constants are float32 literals that read
// back to the same float32 value (with an `f` suffix where the language needs one).
//
// With CodegenOptions::precision = Precision::Half the function computes in binary16 (GLSL
// float16_t, HLSL and Metal half, CUDA __half plus a __half2 twin NAME_x2 that computes two
// values at once), every step rounding where evaluate_half (eval/evaluate_in.hpp) rounds: the
// program of a half DAG (cost/dag.hpp), with fma only where the formula has one (docs/precision.md,
// "Half code").
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "shaderfit/expr/expression.hpp"
#include "shaderfit/expr/precision.hpp"

namespace shaderfit {

enum class Language : std::uint8_t { Glsl, Hlsl, Cuda, Cpp, Metal };

struct CodegenOptions {
  Language language = Language::Glsl;
  std::string name = "shaderfit_formula";  // the function's name
  // Parameters become named constants (`const float s = 0.25f;`) holding
  // Expression::parameter_values when true; otherwise they are arguments after the inputs.
  bool bake_parameters = false;
  // Comment lines printed above the function (without the comment marker), e.g. the formula.
  std::vector<std::string> comment;
  // Per-material inputs (cost/per_material.hpp). A formula that reads one is printed in two
  // parts, as the cost model splits it: `struct NAME_material { float m0; ... };`, the function
  // `NAME_material NAME_material_values(uniform inputs)` that computes the hoisted values once
  // per material, and `float NAME(varying inputs, NAME_material m)` per pixel.
  std::vector<std::string> uniform;
  // The arithmetic of the printed function: Float (float32) or Half (binary16; no C++ form, no
  // two-part form, no sign, copysign, select or asin ... erf). Double has no form.
  Precision precision = Precision::Float;
};

// The comment line that gives what a function costs under the model: "cost model: 5 SASS, 5 PTX,
// 6 generic instructions", or with per-material inputs read "cost model: per pixel 3 SASS, 3 PTX,
// 4 generic; per material 6 SASS, 6 PTX, 6 generic instructions"; in half "cost model: 4 SASS
// per __half2 (2 per value)", the `sass-half2` target.
std::string cost_comment(const Expression& e, std::span<const std::string> uniform = {},
                         Precision precision = Precision::Float);

// The names of a two-part formula's struct and per-material function.
std::string material_type_name(const std::string& function_name);      // NAME_material
std::string material_function_name(const std::string& function_name);  // NAME_material_values
// The name of CUDA's __half2 form of a half function: NAME_x2.
std::string pair_function_name(const std::string& function_name);

// One function, ending in a newline; in GLSL, HLSL and Metal, which have no erf, a formula with
// erf is preceded by the helper function it calls (`sf_erf`, max error 1.32 ulp in float32
// arithmetic; docs/codegen.md). In half: a first comment line naming what the file needs (GLSL's
// #extension, HLSL's 16-bit types, CUDA's cuda_fp16.h), in CUDA the __half helpers the function
// calls (codegen/spelling.hpp), the __half function (__host__ __device__) and NAME_x2 (__device__).
// Throws shaderfit::Error (located at CodegenOptions::name, Expression::variables,
// Expression::parameters or "formula") for a function, input or parameter name that is not an
// identifier of the language or is reserved there, and for a constant that is not finite; at
// CodegenOptions::precision for Double and for half C++, at CodegenOptions::uniform for half with
// per-material inputs, at "formula" for an operator that has no half form.
std::string generate_function(const Expression& e, const CodegenOptions& options);

// One function of a source file: the formula and how to print it.
struct SourceFunction {
  Expression expression;
  CodegenOptions options;  // options.language is not read: generate_source's language is used
};

// A source file that compiles on its own, pasted into an empty file: the lines its functions need
// first, the erf helper once where a function needs it (GLSL, HLSL, Metal), then the functions
// with a blank line between, each in its own options.precision. Those lines:
//   C++    #include <cmath> when a function calls std::fma, std::sqrt, std::copysign, ...;
//          #include <algorithm> for std::clamp (saturate; C++17)
//   GLSL   #version 450: glslangValidator reads a file without one as ES 1.00 (no uint, no
//          floatBitsToUint, no SPIR-V); inside a shader that has its own #version line the
//          functions need 3.30 (ES 3.00) where they use copysign, any version otherwise
//   Metal  #include <metal_stdlib> and using namespace metal;
//   CUDA and HLSL: none (their math functions are built in).
// In half: GLSL adds #extension GL_EXT_shader_explicit_arithmetic_types_float16 : require; HLSL
// a comment that half needs 16-bit types (DXC -enable-16bit-types, glslangValidator
// --hlsl-enable-16bit-types); CUDA #include <cuda_fp16.h> and the helpers once.
// A shader stage still needs its entry point (GLSL void main(), an HLSL entry) after the text.
// Throws as generate_function.
std::string generate_source(std::span<const SourceFunction> functions, Language language);

// `v` rounded to float32, as the shortest literal of the language that reads back to it:
// "0.5f", "1.0f", "1e-05f" (HLSL, CUDA, C++, Metal), "0.5", "1.0" (GLSL). Throws shaderfit::Error
// for NaN or infinity.
std::string float32_literal(double v, Language language);

// `v` rounded to binary16, as the shortest literal that reads back to it (rounded to binary16
// directly or through float32): "0.1hf" (GLSL), "0.1h" (HLSL, Metal), "__float2half(0.1f)"
// (CUDA). Throws shaderfit::Error for NaN, a value that rounds to infinity, and for C++ (no half
// type), at CodegenOptions::precision.
std::string half_literal(double v, Language language);

// "glsl" / "hlsl" / "cuda" / "cpp" / "metal"; nullopt for any other name.
std::optional<Language> language_from_name(std::string_view name);
std::string_view language_name(Language language);

}  // namespace shaderfit
