// Rational functions P_m(t) / Q_n(t) in a variable t = offset + scale * x, and their forms.
//
//   RationalForm form{2, 1, Transform::identity()};       // (p0 + p1 t + p2 t^2) / (1 + q1 t)
//   std::vector<RationalForm> all = enumerate_forms(4, {Transform::identity(),
//                                                       Transform::reflection({0, 1})});
//   // 3/0, 2/1, 1/2, 0/3 in x and in 1 - x: Schlick's "cubic; quadratic over linear; ..."
//   Rational r{form, {1, 2, 3}, {1, 0.5}};
//   double y = r(0.25);
//   Expression e = r.to_expression("x");   // Horner form, for the cost model and printing
//
// Q is normalised by q0 = 1, so a form has (m + 1) + n free coefficients.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "shaderfit/expr/expression.hpp"
#include "shaderfit/rational/target.hpp"

namespace shaderfit::rational {

// The variable a form is written in: t = offset + scale * x (scale != 0).
struct Transform {
  double offset = 0.0, scale = 1.0;

  static Transform identity() { return {}; }
  // t = lo + hi - x: the domain mirrored onto itself (1 - x on [0, 1]).
  static Transform reflection(Interval domain) { return {domain.lo + domain.hi, -1.0}; }
  // Parses an affine formula in `variable` ("1 - cos", "x - 1", "2*x - 1"). Throws
  // shaderfit::Error at `source` if it does not parse or is not affine with a nonzero slope.
  static Transform parse(std::string_view text, const std::string& variable,
                         const std::string& source = "Transform");

  [[nodiscard]] bool is_identity() const { return offset == 0.0 && scale == 1.0; }
  [[nodiscard]] double operator()(double x) const { return offset + scale * x; }
  // "x", "1 - x", "x - 1", "2 * x - 1".
  [[nodiscard]] std::string text(const std::string& variable) const;
  // The same transform as an expression over {variable}.
  [[nodiscard]] Expression expression(const std::string& variable) const;

  friend bool operator==(const Transform&, const Transform&) = default;
};

struct RationalForm {
  int numerator_degree = 0;    // m
  int denominator_degree = 0;  // n
  Transform variable;

  [[nodiscard]] int coefficient_count() const { return numerator_degree + 1 + denominator_degree; }
  [[nodiscard]] bool is_polynomial() const { return denominator_degree == 0; }
  // "2/1", with " in 1 - x" when the variable is not x itself.
  [[nodiscard]] std::string name(const std::string& variable) const;

  friend bool operator==(const RationalForm&, const RationalForm&) = default;
};

// Every form with `coefficients` free coefficients in each transform, numerator degree
// descending within a transform: (c-1)/0, (c-2)/1, ..., 0/(c-1). Equal transforms are used once.
// A polynomial is the same function in every affine variable, but its Horner form (and so its
// cost) is not: F0 + (1 - F0)(1 - x)^5 is cheap in 1 - x and dense in x, so each is listed.
std::vector<RationalForm> enumerate_forms(int coefficients,
                                          const std::vector<Transform>& transforms);

// Parses "m/n" (or "m" for a polynomial). Throws shaderfit::Error at `source` otherwise.
RationalForm parse_form(std::string_view text, const std::string& source = "RationalForm");

struct Rational {
  RationalForm form;
  std::vector<double> p;  // m + 1 numerator coefficients, lowest power first
  std::vector<double> q;  // n + 1 denominator coefficients, q[0] = 1

  [[nodiscard]] double numerator(double x) const;
  [[nodiscard]] double denominator(double x) const;
  [[nodiscard]] double operator()(double x) const { return numerator(x) / denominator(x); }

  // The function in Horner form over the single variable `variable`: P alone when n = 0, zero
  // coefficients skipped (p0 + t^2 (p2 + t p3)), the transform written out (1 - x).
  [[nodiscard]] Expression to_expression(const std::string& variable) const;
  // Coefficients with |c| below `relative` times the largest of P (or Q) set to exactly 0.
  void clean(double relative = 1e-13);
};

// A point of [domain.lo, domain.hi] where the denominator vanishes (a sign change, or a minimum
// of |Q| below `relative_floor` times max |Q|), found by dense sampling, bisection and
// golden-section refinement of the sampled minima; nullopt if Q keeps one sign well away from 0.
std::optional<double> denominator_zero(const Rational& r, Interval domain,
                                       double relative_floor = 1e-9);

}  // namespace shaderfit::rational
