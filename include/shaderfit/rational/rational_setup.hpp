// Building a rational-approximation problem from a description in text: the target (a built-in,
// or a formula or shader function in the reference language), its parameters (one of which may
// take several values: a sweep), the domain, the conditions, and the forms to solve. What
// `shaderfit rational` runs; docs/rational.md describes each field's syntax.
//
//   RationalSetup setup;
//   setup.target = "fresnel-dielectric-f0";
//   setup.parameters = {"F0=0.04,0.5"};
//   setup.forms = {"5/0"};
//   setup.transforms = {"1 - cos"};
//   setup.conditions = {"f(0)=1", "f(1)=F0", "f'(1)=0"};
//   PreparedRational r = prepare_rational(setup);
//   RationalReport report = solve_prepared(r);  // a run at F0 = 0.04 and one at 0.5, and how
//                                               // each coefficient varies with F0
//
// Bad input throws shaderfit::Error located at the field ("RationalSetup::conditions", with the
// 1-based position of a list entry as the line); the reference language's errors at
// "RationalSetup::target" with line and column, or at the shader file's line and column.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "shaderfit/rational/parametric.hpp"
#include "shaderfit/rational/solve.hpp"

namespace shaderfit::rational {

struct RationalSetup {
  // A built-in name, or a formula of the reference language (docs/reference.md: acos(x),
  // erf(x), atan2(x, 1), ...) in `variable` whose other names are the parameters; or empty, and
  // the function `function` of the GLSL or HLSL source `reference_source` (the text of the file
  // `reference_path`): its parameter named `variable`, or else its one parameter without a value
  // in `parameters`, is the variable.
  std::string target;
  std::string variable = "x";
  std::string reference_source;
  std::string reference_path;
  std::string function;
  std::string domain;                   // "LO,HI" or "x=LO:HI"; empty: the natural domain
  std::vector<std::string> conditions;  // f(a)=v, f'(a)=v, f^(k)(a)=v, int(a,b)=v
  std::vector<std::string> forms;       // "m/n", each in every transform
  std::vector<std::string> transforms;  // the forms' variable, affine in the target's variable
  std::vector<std::string> parameters;  // NAME=V1[,V2...]; at most one takes several values
  int count = 0;                        // RationalOptions::coefficient_count (not with forms)
  Fit fit = Fit::None;
  bool relative_minimax = false;
  Loss rank_by = Loss::Rmse;
};

struct PreparedRational {
  RationalProblem problem;  // parameter values: the first of each parameter's values
  RationalOptions options;
  int sweep = -1;                    // the parameter that takes several values, or -1
  std::vector<double> sweep_values;  // its values ({0} without a sweep)
  std::size_t transform_count = 1;   // problem.forms holds each form this many times in a row
};

PreparedRational prepare_rational(const RationalSetup& setup);

// What a prepared problem gives: one run per value of the swept parameter (or one run), and the
// coefficients' laws over the sweep.
struct RationalRun {
  std::vector<double> parameter_values;  // in the order of RationalReport::parameter_names
  RationalSummary summary;
};

struct RationalReport {
  std::string target, variable;
  Interval domain;
  Fit fit = Fit::None;
  std::vector<std::string> conditions;
  std::vector<std::string> parameter_names;
  std::vector<RationalRun> runs;
  // With a sweep over a range: the swept parameter, the range, and each form's coefficients
  // as functions of it.
  std::string swept_parameter;
  Interval sweep_range;
  std::vector<ParametricLaw> laws;
};

// "none", "lsq", "minimax": the names RationalSetup's text and the JSON use.
std::string_view fit_name(Fit fit);

// Solves the prepared problem at each sweep value (prepared.problem's parameter values end at
// the last), then fits the coefficients' laws when the sweep spans a range. Throws
// shaderfit::Error located at RationalSetup::forms (line: the form's position) when a form the
// setup names explicitly has a pole in the domain, or when the best of the named forms is not
// usable (singular, ill-conditioned, not converged).
RationalReport solve_prepared(PreparedRational& prepared);

}  // namespace shaderfit::rational
