// Schlick's kernel-conditions method: rational approximations from conditions, ranked.
//
//   RationalProblem problem;
//   problem.target = Target::builtin("fresnel-dielectric-f0");
//   problem.parameter_names = {"F0"};
//   problem.parameter_values = {0.04};
//   problem.domain = {0, 1};
//   for (const char* c : {"f(0) = 1", "f(1) = F0", "f'(1) = 0", "f''(1) = 0", "f'''(1) = 0",
//                         "f^(4)(1) = 0"})
//     problem.conditions.push_back(parse_condition(c, problem.parameter_names));
//   RationalOptions options;               // forms: every m/n with 6 coefficients, in x and 1 - x
//   std::string why;
//   if (!options.is_valid(&why)) { ... }
//   RationalSummary summary;
//   solve(options, problem, &summary);
//   std::cout << summary.full_report();    // 5/0 in 1 - cos: 0.04 + 0.96 * (1 - cos)^5 ...
//
// Each form P_m / Q_n with (m + 1) + n coefficients (q0 = 1) is solved from the conditions:
//  - values and derivatives are linear in the coefficients once multiplied through by Q:
//    (P - f Q)^(k)(a) = 0, expanded by Leibniz with the lower derivatives of f at a that the
//    conditions also give; such systems are solved directly, with their condition number;
//  - an integral of a rational, or a derivative whose lower orders are not all given at the
//    point, is nonlinear: Newton (Gauss-Newton with a line search) from a linearised fit;
//  - with Fit::LeastSquares or Fit::Minimax, coefficients beyond the conditions are fitted to
//    the reference (conditions kept exact); with Fit::LeastSquares and more conditions than
//    coefficients, the conditions are met in the least-squares sense.
// A form whose denominator vanishes on the domain is rejected (status PoleInDomain). Every usable
// form gets its RMSE, max absolute and max relative error against the reference on a uniform
// grid, and its instruction cost (the Horner form given to expression_cost).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "shaderfit/core/progress.hpp"
#include "shaderfit/eval/loss.hpp"
#include "shaderfit/expr/expression.hpp"
#include "shaderfit/expr/print.hpp"
#include "shaderfit/rational/condition.hpp"
#include "shaderfit/rational/minimax.hpp"
#include "shaderfit/rational/rational_function.hpp"
#include "shaderfit/rational/target.hpp"

namespace shaderfit::rational {

enum class Fit { None, LeastSquares, Minimax };

struct RationalProblem {
  Target target = Target::builtin("exp");
  // Every name a condition or the target may use, with its value. Must include the target's
  // parameters; may hold more (k in "f'(0) = 1/k").
  std::vector<std::string> parameter_names;
  std::vector<double> parameter_values;
  Interval domain;
  std::vector<Condition> conditions;
  std::vector<RationalForm> forms;  // the forms to solve; empty: enumerate (see RationalOptions)

  // Throws shaderfit::Error for: names and values of different counts, a target parameter with
  // no value, a non-finite value, an empty or non-finite domain, a condition outside the domain
  // (located at the condition's point), a derivative order out of range.
  void validate() const;
  // The values of the target's parameters, in the target's order.
  [[nodiscard]] std::vector<double> target_parameter_values() const;
};

struct RationalOptions {
  // Forms enumerated when the problem lists none: every m/n with this many coefficients in each
  // of `transforms`. 0 = as many coefficients as conditions.
  int coefficient_count = 0;
  std::vector<Transform> transforms;  // empty: x and the domain's reflection (1 - x on [0, 1])
  Fit fit = Fit::None;
  bool relative_minimax = false;  // Fit::Minimax of |error / f| instead of |error|
  // The error the results are ranked by: Loss::Rmse, MaxAbs or MaxRel (FormResult's rmse,
  // max_abs, max_rel); other losses are refused (Error at RationalOptions::rank_by).
  Loss rank_by = Loss::Rmse;
  double ill_conditioned = 1e10;  // linear systems with a larger condition number are flagged
  int samples = 2049;             // uniform points for the error metrics and least squares
  MinimaxOptions minimax;
  // Told of the forms solved so far (solve), or of the forms of every sweep value
  // (solve_prepared); core/progress.hpp.
  ProgressCallback on_progress;

  [[nodiscard]] bool is_valid(std::string* why) const;
};

enum class FormStatus { Ok, IllConditioned, Singular, PoleInDomain, NotConverged, Failed };
const char* form_status_name(FormStatus s);  // "ok", "ill-conditioned", "singular", ...

struct FormResult {
  RationalForm form;
  FormStatus status = FormStatus::Failed;
  std::string message;  // why it is not usable, or a note ("condition number 3e+11")
  Rational rational;
  double condition_number = 0;  // of the linear system solved; 0 when there was none
  double rmse = 0, max_abs = 0, max_rel = 0;
  double cost = 0;        // expression_cost(expression, CostTarget::Instructions)
  Expression expression;  // Horner form over the target's variable
  std::string formula;    // to_infix(expression)
  std::optional<Equioscillation> minimax;

  [[nodiscard]] bool usable() const {
    return status == FormStatus::Ok || status == FormStatus::IllConditioned;
  }
  // rmse, max_abs or max_rel for Loss::Rmse, MaxAbs, MaxRel; throws Error for the others.
  [[nodiscard]] double error(Loss by) const;
};

struct RationalSummary {
  std::string variable;  // the target's variable, as the formulas use it
  Loss rank_by = Loss::Rmse;
  std::vector<FormResult> results;  // usable forms by ascending error, then the others
  std::vector<std::size_t> pareto;  // indices of results on the error-cost front, cheapest first

  // One line; and the ranked table with the front. Formulas are written as `print` says.
  [[nodiscard]] std::string brief_report(
      const PrintOptions& print = PrintOptions::for_people()) const;
  [[nodiscard]] std::string full_report(
      const PrintOptions& print = PrintOptions::for_people()) const;
};

// Solves one form. Throws shaderfit::Error for input that no form could satisfy (more conditions
// than coefficients without a fit, fewer without one, a nonlinear condition kept in a rational
// minimax); numerical trouble with this form is reported in the result's status instead.
FormResult solve_form(const RationalOptions& options, const RationalProblem& problem,
                      const RationalForm& form);
// Validates, solves every form and ranks them.
void solve(const RationalOptions& options, const RationalProblem& problem,
           RationalSummary* summary);

}  // namespace shaderfit::rational
