// Printing expressions: infix that parse_formula reads back to an expression of the same value,
// and LaTeX.
//
//   to_infix(e)  == "r0 + (x - r0) * x^4"
//   to_latex(e)  == "r_0 + \\left(x - r_0\\right) x^{4}"
//   to_infix(e, PrintOptions::for_people())  // fitted constants as short as float32 allows
#pragma once

#include <string>

#include "shaderfit/expr/expression.hpp"

namespace shaderfit {

// How a constant is written.
enum class NumberText {
  Exact,    // the shortest decimal that reads back to the same double (JSON, checkpoints, parsing)
  Float32,  // the shortest decimal that reads back to the same float32: the value a shader uses
  Digits,   // PrintOptions::digits significant digits (fewer where they suffice)
};

struct PrintOptions {
  // Print Param nodes as their current values instead of their names.
  bool substitute_parameters = false;
  NumberText numbers = NumberText::Exact;
  int digits = 0;  // for NumberText::Digits: 1 to 17
  // As a person writes it: repeated factors as powers, literal factors first, exp and log
  // where the constants log2(e) and ln(2) appear. The text reads back to a formula of the same
  // instruction count whose value is equal up to float rounding (the order of products).
  bool natural = false;

  // What people read (tables, progress lines, reports, code comments, plot labels): parameters
  // as their values, constants as NumberText::Float32, or with `digits` significant digits when
  // `digits` > 0. Throws shaderfit::Error (at "PrintOptions::digits") for digits outside 0..17.
  static PrintOptions for_people(int digits = 0);
};

// Infix with the fewest parentheses that keep the structure. Parts whose text would read as
// neutral are left out: a literal factor or divisor written `1`, a literal addend or subtrahend
// written `0`, and `^1` (e.g. `x * 1.0000000001` with NumberText::Float32 is written `x`), so
// no text shows `x * 1`, `x / 1`, `x + 0`, `x - 0`, `0 + x`, `1 * x` or `x^1`. Signs move
// outward through products, quotients, sums and odd functions, and drop at even ones, until
// the whole formula or a function's argument shows them: no text shows `* -`, `/ -`, `- -`,
// `+ -`, and a negated sum is written with its terms' signs flipped (`-(a + b)` is `-a - b`,
// `-(a - b)` is `b - a`); a sum shows a positive term first and a literal term last, a product
// a literal factor first (`c * x`). Each of these is exact up to the sign of a zero or a NaN.
// With NumberText::Exact, parse_formula(to_infix(e), {variables, parameters}) evaluates equal
// to e on every input, and printing what it reads gives the same text again; with
// NumberText::Float32 it evaluates equal in float32, and with PrintOptions::natural up to
// float rounding.
std::string to_infix(const Expression& e, const PrintOptions& options = {});

// LaTeX for reports: x^{4}, \sqrt{x}, \frac{a}{b}, identifiers with a trailing digit subscripted.
std::string to_latex(const Expression& e, const PrintOptions& options = {});

// The shortest decimal text that reads back to exactly `v` (no exponent for "ordinary" values).
std::string format_number(double v);
// `v` as options.numbers says ("nan", "inf", "-inf" for the values that are not finite).
std::string format_number(double v, const PrintOptions& options);

}  // namespace shaderfit
