// Kernel conditions (Schlick 1994): what an approximation must reproduce exactly.
//
//   std::vector<std::string> params = {"F0"};
//   Condition a = parse_condition("f(0) = 1", params);          // a value
//   Condition b = parse_condition("f(1) = F0", params);         // a value given by a parameter
//   Condition c = parse_condition("f''(1) = 0", params);        // a derivative (also f^(4)(1))
//   Condition d = parse_condition("int(0, 1) = ref", params);   // the reference's own integral
//   Condition e = Condition::derivative(0.0, 1, 2.0);           // built in code: f'(0) = 2
//
// Syntax: NAME ['...] (POINT) = VALUE, NAME^(K)(POINT) = VALUE or NAME^K(POINT) = VALUE for a
// derivative of order K >= 0 (primes count orders 1 to 3), and int(A, B) = VALUE (also
// integral(A, B)) for the integral from A to B. NAME is any identifier (f, F, G). POINT, A and B
// are constant formulas (0.5, pi/4); VALUE is a formula over the parameters (1, F0, 1/k) or `ref`,
// the reference function's own value, derivative or integral, computed numerically.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "shaderfit/core/error.hpp"
#include "shaderfit/expr/expression.hpp"

namespace shaderfit::rational {

struct Condition {
  enum class Kind { Derivative, Integral };  // a value is the derivative of order 0
  Kind kind = Kind::Derivative;
  int order = 0;        // derivative order (Derivative)
  double a = 0, b = 0;  // the point (Derivative), or the bounds of the integral
  bool from_reference = false;
  Expression value;  // over the problem's parameter names (as parameters); unused if from_reference
  std::string text;  // as written, or as built
  SourceLocation where;  // where it came from (RationalProblem::conditions, line = position)
  int point_column = 0;  // 1-based column of the point (or first bound) in `text`, 0 if built

  static Condition derivative(double at, int order, double value);
  static Condition value_at(double at, double value) { return derivative(at, 0, value); }
  static Condition integral(double from, double to, double value);
  static Condition derivative_of_reference(double at, int order);
  static Condition integral_of_reference(double from, double to);

  [[nodiscard]] bool is_integral() const { return kind == Kind::Integral; }
  // Location of the point for error messages: `where` with the column of the point.
  [[nodiscard]] SourceLocation point_location() const;
};

// Parses one condition. Names in VALUE must be among `parameters`. Throws shaderfit::Error at
// `where` with the 1-based column of the problem: a syntax error, a negative or too high order,
// a point that is not a constant, an unknown name.
Condition parse_condition(std::string_view text, const std::vector<std::string>& parameters,
                          SourceLocation where = {"RationalProblem::conditions", 0, 0});

// "f(0) = 1", "f'''(1) = 0", "f^(4)(1) = ref", "int(0, 1) = 0.5" for conditions built in code.
std::string condition_text(const Condition& c);

}  // namespace shaderfit::rational
