// The arithmetic a formula is computed in, as the shader runs it: float64 (the search's own),
// float32 (`float`) or IEEE binary16 (`half`: GLSL float16_t / mediump, HLSL half, CUDA __half,
// Metal half), and rounding to binary16. How a whole expression is evaluated in each is
// eval/evaluate_in.hpp; codegen and the cost model name the precision with this enum.
//
//   double h = round_to_half(0.1);  // 0.0999755859375
#pragma once

#include <optional>
#include <string_view>

#include "shaderfit/core.hpp"
#include "shaderfit/core/error.hpp"

namespace shaderfit {

enum class Precision : std::uint8_t { Double, Float, Half };

// "double" (also "float64"), "float" ("float32", "single"), "half" ("float16"); nullopt otherwise.
std::optional<Precision> precision_from_name(std::string_view name);
std::string_view precision_name(Precision p);  // "double", "float", "half"
// The same, or shaderfit::Error at `where` that lists the known names.
Precision parse_precision(std::string_view name, const SourceLocation& where);

// The largest finite binary16 value.
inline constexpr double kHalfMax = 65504.0;

// v rounded to the nearest binary16 value (ties to even; subnormals kept; +-inf from 65520 on;
// NaN stays NaN), as a double. Exact: no intermediate float rounding.
double round_to_half(double v);

// One half unit in the last place at v: the spacing of binary16 values at |v| (2^-24 below
// 2^-14); infinity for |v| beyond kHalfMax.
double half_ulp(double v);

}  // namespace shaderfit
