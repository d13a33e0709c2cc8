// Parsing formulas written in infix, as users type them and as shaderfit prints them.
//
//   ParseOptions opts;
//   opts.variables = {"r0", "x"};
//   Expression e = parse_formula("r0 + (1 - r0) * pow(x, 5)", opts);
//
// Grammar: + - * / with the usual precedence, unary minus, `^` with an integer exponent from -16
// to 16 (x^4, x^-2; binds tighter than unary minus, so -x^2 = -(x^2)), parentheses, calls
// sqrt rsqrt rcp exp2 log2 exp log abs saturate sin cos sign (one argument), min max pow copysign
// (two), fma (three), `pow(a, k)` with an integer literal k in range becomes the integer power,
// numbers in decimal or scientific notation, the constant `pi`, and identifiers
// [A-Za-z_][A-Za-z0-9_]*. A minus sign directly before a number literal makes a negative constant
// (`-0.5`).
//
// `select(X cmp Y, b, c)` with cmp one of >= > <= <, or C's `X cmp Y ? b : c` (lowest in
// precedence, nesting to the right; the comparison may stand in parentheses), is the one
// comparison of the grammar (an error anywhere else) and becomes the operator
// select(a, b, c) = a >= 0 ? b : c:
//   select(X >= Y, b, c) -> select(X - Y, b, c)     select(X <= Y, b, c) -> select(Y - X, b, c)
//   select(X > Y, b, c)  -> select(Y - X, c, b)     select(X < Y, b, c)  -> select(X - Y, c, b)
// where a literal zero for the subtrahend is dropped (X >= 0: a = X) and one for the minuend makes
// a negation (0 >= Y: a = -Y). The forms agree with the comparisons except where the difference
// is NaN (X = Y = +-inf; and > and < take b for a NaN operand). The printer writes a select as
// `select(a >= 0, b, c)`, which reads back to the same nodes (for people, a difference as its
// comparison: `select(x <= 0.5, b, c)`).
//
// Size limits, far above any formula a shader would use, so that nothing that walks a parsed
// formula recursively (the parser itself, the printers, simplify, the cost model) can run out of
// stack on a hostile input: parentheses, calls and unary signs nest at most kMaxFormulaNesting
// levels, and the tree is at most kMaxFormulaDepth operations deep (a sum of that many terms).
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "shaderfit/expr/expression.hpp"

namespace shaderfit {

inline constexpr int kMaxFormulaNesting = 256;
inline constexpr int kMaxFormulaDepth = 2048;

struct ParseOptions {
  // Names allowed as input variables. When empty, every identifier that is not a parameter or a
  // function becomes a variable, in order of first appearance.
  std::vector<std::string> variables;
  // Names that denote free parameters. Their values start at `parameter_values` (if given, one per
  // name) or 0.
  std::vector<std::string> parameters;
  std::vector<double> parameter_values;
  // Every number literal becomes a further free parameter, named p0, p1, ... (names already
  // taken are skipped) and starting at the literal's value; named constants (pi) and integer
  // exponents (x^5, pow(x, 5)) stay exact.
  bool literals_as_parameters = false;
  // Name used as the source of error locations ("formula", "baseline 1", a file name...).
  std::string source = "formula";
  int line = 1;
};

// Throws shaderfit::Error naming the source, line and column of the first problem: a syntax error,
// an unknown function, a wrong number of arguments, an exponent out of range, an unknown variable,
// a formula beyond the size limits above.
// The result's variable table is `options.variables` (when given) or the names in order of use;
// its parameter table is `options.parameters` (followed by the literals, with
// literals_as_parameters).
Expression parse_formula(std::string_view text, const ParseOptions& options = {});

}  // namespace shaderfit
