// Coefficients as functions of a parameter: when a target has a parameter (F0, alpha), the
// solution of a form is found at many values of it, and each coefficient is tested for being a
// low-degree rational function of the parameter, fitted on some values and verified on others.
//
//   RationalProblem problem = ...;  // Schlick's conditions, parameter F0
//   std::vector<ParametricLaw> laws =
//       parametric_laws({}, problem, "F0", {0.02, 0.9}, {{5, 0, Transform::reflection({0, 1})}});
//   laws[0].all_rational == true;
//   laws[0].formula == "F0 + (1 - F0) * (1 - cos)^5";
//   laws[0].coefficients[0].law == "F0";   // p0
#pragma once

#include <string>
#include <vector>

#include "shaderfit/expr/expression.hpp"
#include "shaderfit/rational/solve.hpp"

namespace shaderfit::rational {

struct ParametricOptions {
  int fit_values = 12;      // parameter values the laws are fitted on (Chebyshev points)
  int check_values = 7;     // other values they must reproduce
  int max_degree = 4;       // of numerator plus denominator, in the parameter
  double tolerance = 1e-9;  // largest deviation allowed, relative to 1 + max |coefficient|

  [[nodiscard]] bool is_valid(std::string* why) const;
};

struct CoefficientLaw {
  std::string coefficient;  // "p0", "q1"
  bool found = false;
  Expression expression;     // over the parameter alone (as a variable); empty if not found
  std::string law;           // to_infix(expression), or why none was found
  double max_deviation = 0;  // on the check values
};

struct ParametricLaw {
  RationalForm form;
  bool usable = false;        // the form was usable at every value tried
  bool all_rational = false;  // every coefficient has a law
  // p0..pm, q1..qn with q0 = 1; or p0..pm, q0..qn with the numerator's lowest nonzero
  // coefficient set to 1 (listed as "1"), when that gives smaller laws: Schlick's G is
  // v / (k + (1 - k) v) rather than (v / k) / (1 + (1 - k) / k v).
  std::vector<CoefficientLaw> coefficients;
  Expression expression;  // the approximation over {variable, parameter}, if all_rational
  std::string formula;    // to_infix(expression), if all_rational
  std::string note;       // why not, when not usable
};

// For each form, solves `problem` with `parameter` set to values spread over `range` (other
// parameters as given) and looks for laws. Throws shaderfit::Error if `parameter` is not one of
// the problem's parameter names, the range is empty, or a solve throws.
std::vector<ParametricLaw> parametric_laws(const RationalOptions& options,
                                           const RationalProblem& problem,
                                           const std::string& parameter, Interval range,
                                           const std::vector<RationalForm>& forms,
                                           const ParametricOptions& parametric = {});

}  // namespace shaderfit::rational
