// Conditions as equations in a form's coefficients (internal to src/rational).
//
// Coefficients are ordered [p_0 .. p_m, q_0 .. q_n] ("homogeneous": q_0 is kept as an unknown,
// and rows have no right-hand side) or [p_0 .. p_m, q_1 .. q_n] with q_0 = 1 ("normalised").
// Derivative conditions are written in Taylor coefficients (f^(k)(a) / k!), which keeps rows of
// different orders on comparable scales.
#pragma once

#include <Eigen/Dense>
#include <optional>
#include <span>
#include <vector>

#include "shaderfit/rational/condition.hpp"
#include "shaderfit/rational/rational_function.hpp"
#include "shaderfit/rational/solve.hpp"

namespace shaderfit::rational_detail {

using namespace shaderfit::rational;  // the area's public names

struct ResolvedCondition {
  const Condition* source = nullptr;
  bool integral = false;
  int order = 0;
  double a = 0, b = 0;
  double value = 0;   // f^(k)(a), or the integral
  double taylor = 0;  // value / k! (the integral itself for an integral)
};

// Numeric right-hand sides: parameter formulas evaluated, `ref` taken from the target.
std::vector<ResolvedCondition> resolve_conditions(const RationalProblem& problem);

// The homogeneous row of `c` for `form`, or nullopt when the condition is not linear in the
// coefficients: an integral of a rational, or a derivative of order k at a whose lower Taylor
// coefficients f_j (j from k - n to k) are not all fixed by value conditions at a.
std::optional<Eigen::RowVectorXd> linear_row(const RationalForm& form, const ResolvedCondition& c,
                                             std::span<const ResolvedCondition> all);

// The rational's Taylor coefficient (or integral) minus the condition's, for Newton.
double condition_residual(const Rational& r, const ResolvedCondition& c);

// Coefficient vector (normalised order) <-> Rational.
Rational rational_from(const RationalForm& form, const Eigen::VectorXd& c);
Eigen::VectorXd coefficients_of(const Rational& r);

// Taylor coefficient k at x0 of t^i, t = offset + scale x.
double power_taylor(const Transform& t, int i, double x0, int k);

}  // namespace shaderfit::rational_detail
