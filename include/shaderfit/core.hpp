// shaderfit core: read this header first.
//
// It defines the one host/device macro and forward-declares the types of core, expr, data and
// scene that headers of other areas name, so that those headers need not include their
// definitions. The map of the areas, what each may include and where to add an operator, loss,
// option or language is docs/architecture.md. A program may include the umbrella header
// shaderfit/shaderfit.hpp instead of one header per concept:
//
//   #include <shaderfit/shaderfit.hpp>
//   shaderfit::Expression e =
//       shaderfit::parse_formula("r0 + (x - r0) * x^4", {.variables = {"r0", "x"}});
#pragma once

#include <cstddef>
#include <cstdint>

// SF_CPU_GPU marks functions that compile for both the CPU and, under nvcc, the GPU. Only code
// with no allocation, no exceptions and no virtual calls may carry it.
#if defined(__CUDACC__)
#define SF_CPU_GPU __host__ __device__
#else
#define SF_CPU_GPU
#endif

namespace shaderfit {

// core/
class Error;
struct SourceLocation;

// expr/
enum class Op : std::uint8_t;
struct Node;
struct Expression;
struct ParseOptions;
enum class Precision : std::uint8_t;  // double, float, half: the shader's arithmetic

// data/
struct Dataset;

// problem/
struct ProblemSource;
struct Problem;

// scene/
struct SceneSpec;
struct SceneSamples;

}  // namespace shaderfit
