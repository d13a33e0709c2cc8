// Simplification that never changes the value wherever the original evaluates finitely: constant
// folding (to finite results), neutral and absorbing elements (x + 0, x * 1, x * 0, x / 1, 0 / x),
// x - x = 0, x / x = 1, double negation, a + -b = a - b, x * x = x^2, merging integer powers
// ((x^a)^b, x^a * x^b, x * x^a, x^a / x^b) while the exponent stays in range, 1 / x = rcp(x).
// Where the original or one of its intermediates is NaN or infinite (x - x with x = inf, 1 / -0)
// the simplified value may differ; +0 and -0 count as equal, as under shader fast math.
//
//   Expression s = simplify(parse_formula("(x * x) * 1 + 0", {.variables = {"x"}}));
//   to_infix(s) == "x^2"
#pragma once

#include "shaderfit/expr/expression.hpp"

namespace shaderfit {

Expression simplify(const Expression& e);

}  // namespace shaderfit
