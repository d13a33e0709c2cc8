// The cost of a formula, the second objective of the search (the first is its error).
//
//   Expression e = parse_formula("r0 + (x - r0) * x^4", {.variables = {"r0", "x"}});
//   expression_cost(e, CostTarget::Instructions) == 4   // x - r0, x^2, x^4, one FMA
//   expression_cost(e, CostTarget::Nodes)        == 8   // r0 x r0 - x ^4 * +
//
// Provisional model: the cost-model issue replaces `Instructions` with a SASS-calibrated count
// behind this same interface, so callers must depend on nothing but the function below.
//
// `Instructions` counts GPU arithmetic instructions (FADD/FMUL/FFMA/MUFU-like), after lowering
// the expression to a DAG in which equal subexpressions are computed once:
//  - inputs, parameters and literal constants are free operands (registers or immediates), and
//    subtrees made only of literal constants are folded at compile time (free);
//  - negation is a free operand modifier: `-a`, `1 - a` and `a - b` cost what `a`, one add and one
//    add cost;
//  - + - * are one instruction each, and a product feeding an add or subtract fuses into it (one
//    FMA): `a * b + c` is 1; a product whose every use was fused costs nothing on its own;
//  - x^k by repeated squaring with shared intermediates: x^2 = 1, x^3 = 2, x^4 = 2, x^5 = 3
//    multiplies; x^-k adds one reciprocal;
//  - a / b is a reciprocal and a multiply (2), a / constant one multiply;
//  - sqrt, rsqrt, rcp, exp2, log2, sin, cos: 1 each (one MUFU); exp = 2 and log = 2 (a scale plus
//    exp2/log2); pow(a, b) = exp2(b * log2(a)) = 3; min, max, abs, saturate: 1 each.
// With inputs r0 and x: `r0 + (x - r0)*x^4` costs 4 and Schlick's `r0 + (1 - r0)*x^5` costs 5.
//
// `Nodes` is the number of nodes of the postfix expression (leaves included).
#pragma once

#include <optional>
#include <string_view>

#include "shaderfit/expr/expression.hpp"

namespace shaderfit {

enum class CostTarget { Nodes, Instructions };

// Never negative; 0 only for an expression that is a single leaf (Instructions).
double expression_cost(const Expression& e, CostTarget target);

// "nodes" / "instructions"; nullopt for any other name.
std::optional<CostTarget> cost_target_from_name(std::string_view name);
std::string_view cost_target_name(CostTarget target);

}  // namespace shaderfit
