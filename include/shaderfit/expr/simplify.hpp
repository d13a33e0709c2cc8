// Simplification that never changes the value wherever the original evaluates finitely: constant
// folding (to finite results), neutral and absorbing elements (x + 0, x * 1, x * 0, x / 1, 0 / x),
// x - x = 0, x / x = 1, double negation, a + -b = a - b, x * x = x^2, merging integer powers
// ((x^a)^b, x^a * x^b, x * x^a, x^a / x^b) while the exponent stays in range, 1 / x = rcp(x).
// Where the original or one of its intermediates is NaN or infinite (x - x with x = inf, 1 / -0)
// the simplified value may differ; +0 and -0 count as equal, as under shader fast math.
//
//   Expression s = simplify(parse_formula("(x * x) * 1 + 0", {.variables = {"x"}}));
//   to_infix(s) == "x^2"
//
// SimplifyOptions::regroup_constants adds rules that hold in real arithmetic but round
// differently (used by the search's final tidy step, docs/search.md "Tidy front"):
//   c1 * (c2 * x) = (c1 c2) x, c1 * (x / c2) = x / (c2 / c1), (c1 * x) / c2 = (c1 / c2) x,
//   c * -x = -c * x; like terms collected, a x + b x = (a + b) x, a x - x = (a - 1) x, also one
//   level into a sum ((u + a x) + b x = u + (a + b) x);
//   a factor or an offset taken by a subtree's own constants, never adding a node:
//   p0 * (a x + b) + p1 = (p0 a) x + (p0 b + p1), c * (x - k) + d = c * (x - (k - d / c)),
//   (x + k1) + k2 = x + (k1 + k2), c - (x - k) = (c + k) - x;
//   pow(pow(a, y), z) = pow(a, y z); for a constant a > 0 with a cost callback, the cheaper of
//   that and exp2(log2(a) y z) (pow on a tie).
//   simplify(parse_formula("pow(pow(2.5, x), x)", o), {.regroup_constants = true}) -> pow(2.5, x^2)
#pragma once

#include <functional>

#include "shaderfit/expr/expression.hpp"

namespace shaderfit {

struct SimplifyOptions {
  // The rules above that round differently from the original (the search's inner loops leave
  // them off; its final tidy step uses them).
  bool regroup_constants = false;
  // Two calls of one function that one call does, and a quotient's divisors as one product
  // (they round differently too; each saves an instruction where the parts are not read
  // elsewhere): rcp(a) rcp(b) = rcp(a b), sqrt and rsqrt alike, exp2(a) exp2(b) = exp2(a + b),
  // exp2(a) / exp2(b) = exp2(a - b), exp alike, log2(a) + log2(b) = log2(a b), log alike,
  // pow(a, p) pow(b, p) = pow(a b, p), (u / a) / b = u / (a b), u / rcp(a) = u a, also one
  // level into a product or sum ((u rcp(a)) rcp(b) = u rcp(a b)).
  bool merge_calls = false;
  // The cost of an expression (over the simplified expression's variables and parameters), to
  // choose between equivalent forms; empty: the first form listed above.
  std::function<double(const Expression&)> cost;
};

Expression simplify(const Expression& e, const SimplifyOptions& options = {});

}  // namespace shaderfit
