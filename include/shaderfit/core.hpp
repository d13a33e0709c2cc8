// shaderfit core: read this header first.
//
// It fixes the scalar types, the one host/device macro, and forward-declares the main types of
// every area, so that headers can name each other without including each other. The map of the
// areas, what each may include and where to add an operator, loss, option or language is
// docs/architecture.md.
//
//   #include <shaderfit/core.hpp>
//   shaderfit::Expression e = shaderfit::parse_formula("r0 + (x - r0) * x^4", {"r0", "x"});
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

using f32 = float;
using f64 = double;

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
