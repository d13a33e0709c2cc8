// The cost of a formula, the second objective of the search (the first is its error).
//
//   Expression e = parse_formula("r0 + (x - r0) * x^4", {.variables = {"r0", "x"}});
//   expression_cost(e, CostTarget::Instructions) == 4   // x - r0, x^2, x^4, one FMA
//   expression_cost(e, CostTarget::Nodes)        == 8   // r0 x r0 - x ^4 * +
//
// `Instructions` is the SASS instruction count of the calibrated model
// (cost/instruction_model.hpp: `instruction_count(e, InstructionTarget::Sass)`): the formula is
// lowered to a DAG with equal subexpressions computed once and constants folded; negation is a
// free operand modifier; a product feeding an add is one FFMA; x^k by squaring (x^4 = 2, x^5 = 3);
// a / b = MUFU.RCP + FMUL; sqrt, rsqrt, rcp, exp2, log2 one MUFU; exp, log, sin, cos a scale
// and a MUFU (2); pow(a, b) = 3; min, max, abs, saturate 1. Inputs, parameters and literals are
// free operands. With inputs r0 and x: `r0 + (x - r0)*x^4` costs 4 and Schlick's
// `r0 + (1 - r0)*x^5` costs 5; with cos_theta as input, the Fresnel forms of docs/cost-model.md
// cost 6, 5 and 6, as their SASS listings do.
//
// `Rdna2` and `Rdna3` are the AMD RDNA VALU instruction counts of the same model
// (`instruction_count(e, InstructionTarget::Rdna2)`): a search ranked by them finds the formulas
// that are cheap on those GPUs (docs/cost-model.md, "RDNA").
//
// `Nodes` is the number of nodes of the postfix expression (leaves included).
//
// With per-material (uniform) inputs (cost/per_material.hpp), the cost is the per-pixel part's:
// the subexpressions that read only uniform inputs, literals and parameters are computed once per
// material and are free operands here.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "shaderfit/cost/instruction_model.hpp"
#include "shaderfit/expr/expression.hpp"

namespace shaderfit {

enum class CostTarget { Nodes, Instructions, Rdna2, Rdna3 };

// The instruction target a cost counts on (Instructions: Sass); nullopt for Nodes.
std::optional<InstructionTarget> instruction_target_of(CostTarget target);

// Never negative; 0 only for an expression that is a single leaf (Instructions).
double expression_cost(const Expression& e, CostTarget target);
double expression_cost(const Expression& e, CostTarget target,
                       std::span<const std::string> uniform);

// "nodes" / "instructions" / "rdna2" / "rdna3"; nullopt for any other name.
std::optional<CostTarget> cost_target_from_name(std::string_view name);
std::string_view cost_target_name(CostTarget target);

}  // namespace shaderfit
