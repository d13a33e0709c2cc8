// Printing expressions: infix that parse_formula reads back to the same expression, and LaTeX.
//
//   to_infix(e)  == "r0 + (x - r0) * x^4"
//   to_latex(e)  == "r_0 + \\left(x - r_0\\right) x^{4}"
#pragma once

#include <string>

#include "shaderfit/expr/expression.hpp"

namespace shaderfit {

struct PrintOptions {
  // Print Param nodes as their current values instead of their names.
  bool substitute_parameters = false;
};

// Infix with the fewest parentheses that keep the structure; constants in the shortest decimal
// form that reads back to the same double. parse_formula(to_infix(e), {variables, parameters})
// reproduces e node for node.
std::string to_infix(const Expression& e, const PrintOptions& options = {});

// LaTeX for reports: x^{4}, \sqrt{x}, \frac{a}{b}, identifiers with a trailing digit subscripted.
std::string to_latex(const Expression& e, const PrintOptions& options = {});

// The shortest decimal text that reads back to exactly `v` (no exponent for "ordinary" values).
std::string format_number(double v);

}  // namespace shaderfit
