// Evaluating a shaderfit expression of one variable on a jet (internal to src/rational).
#pragma once

#include <span>

#include "rational/jet.hpp"
#include "shaderfit/expr/expression.hpp"

namespace shaderfit::rational::detail {

// e over the single variable e.variables[0] (every Var node reads `x`); Param node i reads
// params[i]. Semantics follow expr/op.hpp; min, max, abs and saturate pick their branch by the
// value at the point (a kink exactly at the point gives that branch's one-sided derivatives).
Jet evaluate_jet(const Expression& e, const Jet& x, std::span<const double> params);

}  // namespace shaderfit::rational::detail
