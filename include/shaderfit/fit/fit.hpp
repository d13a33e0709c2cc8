// Fitting the free parameters of a formula to data, in the Options + Problem + Summary style.
//
//   ParseOptions po;
//   po.variables = {"r0", "x"};
//   po.parameters = {"a", "b"};
//   po.parameter_values = {1.0, 1.0};  // the starting point
//   Expression e = parse_formula("r0 + (1 - r0) * pow(x, a) * b", po);
//   FitProblem problem{&e, {r0.data(), x.data()}, target};
//   FitSummary summary;
//   fit_parameters(FitOptions{}, problem, &summary);
//   e.parameter_values = summary.parameters;
//
// Formulas linear in their parameters (each parameter enters as a coefficient: p * g(x) + ...)
// are solved directly by linear least squares; others by Levenberg-Marquardt with the exact
// Jacobian from forward-mode differentiation. Both minimise the weighted mean squared error, or,
// with FitOptions::minimax, the weighted max error by Lawson's reweighting of that same fit (the
// one Lawson loop, src/fit/minimax.cpp, which solve_fixed_form's Loss::MaxAbs also runs).
#pragma once

#include <span>
#include <string>
#include <vector>

#include "shaderfit/expr/expression.hpp"

namespace shaderfit {

struct FitOptions {
  int max_iterations = 50;  // Levenberg-Marquardt iterations
  double function_tolerance =
      1e-10;  // stop when a step lowers the cost by less than this, relatively
  double parameter_tolerance =
      1e-10;  // stop when a step moves the parameters by less than this, relatively
  double initial_lambda = 1e-3;   // damping, relative to the diagonal of J^T J
  bool use_linear_solver = true;  // solve formulas linear in their parameters directly
  // Minimise max_i w_i |f_i - y_i| (w = FitProblem::weights, 1 when empty; rows of weight 0 do
  // not count) instead of the weighted mean square: Lawson's iteratively reweighted least
  // squares, each pass a weighted fit of the kind above (LM passes warm-started, at most
  // max_iterations steps each), at most minimax_iterations passes. The result is the best
  // point met, never worse than the start. The summary's costs are then max errors.
  bool minimax = false;
  int minimax_iterations = 300;

  // False, with the reason in *why, for max_iterations or minimax_iterations < 1 or a tolerance
  // or lambda <= 0.
  bool is_valid(std::string* why) const;
};

struct FitProblem {
  const Expression* expression = nullptr;  // its parameter_values are the starting point
  std::vector<const double*> columns;      // one per expression variable, `target.size()` rows each
  std::span<const double> target;
  std::span<const double> weights;  // empty: every row weighs 1
};

struct FitSummary {
  std::vector<double> parameters;  // the fitted values (the start when nothing improved)
  double initial_cost = 0;         // weighted mean squared error (minimax: max error) at the start
  double final_cost = 0;           // and at `parameters`
  int iterations = 0;              // LM steps (or linear solves), over all minimax passes
  int minimax_passes = 0;          // Lawson passes (minimax only)
  bool linear = false;             // solved by linear least squares
  std::string termination;         // "linear", "function tolerance", ..., "minimax converged",
                                   // "minimax iterations"

  [[nodiscard]] std::string brief_report() const;
};

// Throws shaderfit::Error for invalid options, a null expression, or columns that do not match
// the expression's variables. A formula without parameters is only scored.
void fit_parameters(const FitOptions& options, const FitProblem& problem, FitSummary* summary);

// Whether every parameter enters e linearly (e = g0(x) + sum_j p_j g_j(x)): sums, differences
// and negations of linear parts, and products or quotients of a linear part by a part free of
// parameters.
bool is_linear_in_parameters(const Expression& e);

// The most parameters a formula fitted here may have (the forward derivatives track which
// parameters each node reads in one 64-bit mask); more is an Error.
inline constexpr std::size_t kMaxFitParameters = 64;

// Values of e and its Jacobian with respect to e's parameters, by forward-mode differentiation:
// jacobian[j * rows + i] = d e(row i) / d parameter j.
void evaluate_with_jacobian(const Expression& e, std::span<const double* const> columns,
                            std::size_t rows, std::span<double> values, std::span<double> jacobian);

}  // namespace shaderfit
