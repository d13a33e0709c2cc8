// Per-material inputs: what a shader computes once per material (or draw), and what per pixel.
//
//   Expression e = parse_formula("1/(3.14159*alpha^2) * pow(NoH, 2/alpha^2 - 2)");
//   MaterialSplit s = split_per_material(e, {"alpha"});
//   // s.per_pixel  = exp2(m0 * log2(NoH) + m1)            over NoH, m0, m1
//   // s.values     = m0 = 2/alpha^2 - 2, m1 = log2(1/(3.14159*alpha^2))
//   SplitCost c = split_instruction_count(e, {"alpha"}, InstructionTarget::Sass);
//   // c.per_pixel == 3 (MUFU.LG2, FFMA, MUFU.EX2), c.per_material == 6
//
// Uniform inputs are constant over the pixels of a draw (roughness, F0, a lobe's exponent). A
// subexpression that reads uniform inputs, literals and parameters only, and at least one uniform
// input, is a per-material value: computed once per material, each distinct one once, and read
// per pixel as a free operand. The largest such subexpressions are hoisted (a uniform input read
// bare per pixel is a value too, costing nothing), and x / U is x * (1/U) with 1/U hoisted (GPUs
// divide by a reciprocal anyway). One more rewrite moves work out of the pixel:
// U * exp2(x) = exp2(x + log2 U) (also U * pow(a, b), exp2(x) / U, U * exp(x), exp(x) / U with
// log) where U is a per-material value that is >= 0 by its operators (a square, a positive
// literal, exp2, sqrt, ...; log2 of 0 gives exp2(-inf) = 0, as 0 * exp2(x)); it is applied only
// where it lowers the per-pixel count (an FMUL becomes part of an FFMA).
//
// The per-pixel cost is the instruction model's count of `per_pixel` (cost/instruction_model.hpp);
// the per-material cost is its count of the values computed together, shared subexpressions once.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "shaderfit/core/error.hpp"
#include "shaderfit/cost/instruction_model.hpp"
#include "shaderfit/expr/expression.hpp"

namespace shaderfit {

// One hoisted value: a name the per-pixel part reads it by, and how it is computed.
struct MaterialValue {
  std::string name;  // the uniform input's own name when it is read bare, else m0, m1, ...
  Expression value;  // over the formula's variables and parameters
};

struct MaterialSplit {
  // Over the formula's varying inputs (in their order), then the values' names; the formula's
  // parameters (those it still reads).
  Expression per_pixel;
  std::vector<MaterialValue> values;  // in order of first use
};

// Throws shaderfit::Error located at `where` when a uniform name is not one of `inputs`, is
// given twice, or when every input is uniform (nothing would vary over the pixels).
void check_uniform_inputs(std::span<const std::string> uniform, std::span<const std::string> inputs,
                          const SourceLocation& where = SourceLocation{"UniformInputs"});

// Whether any variable of e is named in `uniform`.
bool reads_uniform(const Expression& e, std::span<const std::string> uniform);

// Throws shaderfit::Error for an empty or malformed expression. With no uniform input read,
// per_pixel is e and values is empty.
MaterialSplit split_per_material(const Expression& e, std::span<const std::string> uniform);

struct SplitCost {
  int per_pixel = 0;
  int per_material = 0;
};
SplitCost split_instruction_count(const Expression& e, std::span<const std::string> uniform,
                                  InstructionTarget target);

// The per-material program counted and listed (the values computed together); zero for none.
InstructionCost material_instruction_cost(const MaterialSplit& split, InstructionTarget target);

}  // namespace shaderfit
