// Equality constraints for fixed-form fits, written as text:
//
//   C = 0                 a relation between parameters (any expression in them, = a number)
//   A + B = 2.5
//   f(x = 0) = f0         the formula's value at a point; variables the point does not set come
//                         from the block's context (a grid cell's centre), the right-hand side
//                         may use the same variables
//   df/dx(x = 1) = 0      the formula's derivative with respect to one of its variables
//
//   Constraint c = parse_constraint("f(x = 0) = f0", formula);
//
// A constraint on the formula's value is on the formula itself, not on a transform of it.
#pragma once

#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "shaderfit/expr/expression.hpp"

namespace shaderfit {

struct Constraint {
  enum class Kind { parameters, value, derivative };
  Kind kind = Kind::parameters;
  std::string text;  // as written, for messages
  // Kind::parameters: an expression over the formula's parameters (no variables).
  Expression lhs;
  // Kind::derivative: the variable differentiated by.
  std::string variable;
  // Kind::value and Kind::derivative: the variables the point sets, in the order written.
  std::vector<std::pair<std::string, double>> point;
  // The required value: an expression without parameters, over the formula's variables (read at
  // the point) or none.
  Expression rhs;
};

// Parses one constraint against the formula whose parameters and variables it may name. Throws
// shaderfit::Error located at `source` (column of the problem) for: no '=', an unknown parameter
// or variable, a relation between parameters that uses a variable, a point that sets an unknown
// variable or has a value that is not a number, a derivative by a variable the formula lacks,
// and a right-hand side that uses parameters.
Constraint parse_constraint(std::string_view text, const Expression& formula,
                            const std::string& source = "constraint");

}  // namespace shaderfit
