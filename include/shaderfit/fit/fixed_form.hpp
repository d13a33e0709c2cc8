// Fitting the named free parameters of a fixed formula: globally, per group of the data, or per
// cell of a grid, with a choice of loss, an optional linearising transform, and equality
// constraints. Options + Problem + Summary, as in Ceres.
//
//   FixedFormProblem problem;
//   problem.formula = parse_formula("f0 * exp2(A*x^2 + B*x + C)",
//                                   {.variables = {"f0", "x"}, .parameters = {"A", "B", "C"}});
//   problem.constraints.push_back(parse_constraint("C = 0", problem.formula));
//   problem.blocks.push_back(block);  // FitBlock: columns f0 and x, the target, optional weights
//   FixedFormOptions options;
//   options.loss = Loss::Log;         // fit log2(formula) to log2(target): linear in A, B, C
//   FixedFormSummary summary;
//   solve_fixed_form(options, problem, &summary);
//   std::cout << summary.brief_report();      // summary.blocks[0].parameters = {A, B, 0}
//
// Each block is one independent data set (a group, a grid cell, or all the data). Parameters
// with scope per_block take one value per block; global ones are shared by every block and are
// fitted jointly with the per-block ones. Solvers: when the fitted quantity (the formula, or its
// transform) is linear in the parameters, one constrained linear least-squares solve; otherwise
// Levenberg-Marquardt with forward-mode Jacobians. Loss::MaxAbs minimises the largest weighted
// residual by Lawson's iteratively reweighted least squares. Linear equality constraints are
// eliminated (the solve runs on the remaining free parameters, so they hold exactly); nonlinear
// ones are linearised and the iterate is projected back onto them after every step.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "shaderfit/core/progress.hpp"
#include "shaderfit/eval/loss.hpp"
#include "shaderfit/expr/expression.hpp"
#include "shaderfit/expr/print.hpp"
#include "shaderfit/fit/constraint.hpp"

namespace shaderfit {

enum class SolverKind { automatic, linear, levenberg_marquardt };
// "auto", "linear", "lm" (and back; nullopt for any other name).
std::string_view solver_kind_name(SolverKind kind);
std::optional<SolverKind> solver_kind_from_name(std::string_view name);

enum class ParameterScope { global, per_block };

struct FixedFormOptions {
  // What the fit minimises (eval/loss.hpp), over the residuals f - y with the block weights w:
  //   Mse     sum w (f - y)^2 / sum w, in the transformed space when there is a transform
  //   Log     sum w (log2 f - log2 y)^2 / sum w (the transform log2(y)); targets must be > 0
  //   MaxAbs  max over rows of w |f - y| (weighted minimax), in the transformed space if any
  // Other losses are refused (Error at FixedFormOptions::loss).
  Loss loss = Loss::Mse;
  // automatic: linear least squares when the fitted quantity is linear in the parameters, else
  // Levenberg-Marquardt. linear: fail (Error) when it is not. levenberg_marquardt: always.
  SolverKind solver = SolverKind::automatic;
  int max_iterations = 100;            // Levenberg-Marquardt iterations per solve
  double function_tolerance = 1e-12;   // stop when a step lowers the cost by less, relatively
  double parameter_tolerance = 1e-12;  // stop when a step is smaller, relative to the parameters
  double initial_lambda = 1e-3;        // damping, relative to the diagonal of J^T W J
  int minimax_iterations = 300;        // Lawson reweighting passes for Loss::MaxAbs
  // A design column (after scaling to unit length) whose pivot falls below this, relative to the
  // largest, is dependent on the others: the system is singular.
  double rank_tolerance = 1e-10;
  // A constraint residual below this (relative to 1 + |right-hand side|) is met.
  double constraint_tolerance = 1e-9;
  int threads = 0;  // blocks fitted in parallel; 0 = all cores
  // The joint solve with global parameters works on dense normal equations over all parameters
  // of all blocks; larger problems are refused.
  std::size_t max_coupled_parameters = 2000;
  // Told of the blocks fitted so far when blocks are fitted one by one (not in a joint solve);
  // core/progress.hpp.
  ProgressCallback on_progress;

  // False, with the reason in *why, for a loss the fit does not minimise, a non-positive count
  // or tolerance or a negative thread count.
  bool is_valid(std::string* why) const;
};

// One data set fitted as a unit: a group of rows, or the samples of one grid cell.
struct FitBlock {
  std::string label;  // "material=metal 0.3+3i", "roughness=0.25 f0=0.04": names it in reports
  std::vector<std::vector<double>> columns;  // one per formula variable, in formula order
  std::vector<double> target;                // the reference values
  std::vector<double> weights;               // empty: every row weighs 1; else >= 0, finite
  // Values of conditioning variables that are constant over the block (a grid cell's centre):
  // constraints read the variables their point does not set from here.
  std::vector<std::pair<std::string, double>> context;
};

struct FixedFormProblem {
  // The model. Its parameters are the free parameters, parameter_values their starting values
  // (0 when missing). Its variables are the block columns, in order.
  Expression formula;
  std::vector<ParameterScope> scopes;  // one per parameter; empty: all global
  // Optional transform T(y) over the variable "y" and the formula's variables: the fit minimises
  // the loss of T(formula) - T(target), e.g. log2(y / f0) turns f0 exp2(P) into the polynomial P.
  std::optional<Expression> transform;
  std::vector<Constraint> constraints;
  std::vector<FitBlock> blocks;
};

struct BlockResult {
  std::string label;
  std::vector<double> parameters;  // every parameter's value in this block, formula order
  double initial_cost = 0;         // the loss at the start (MaxAbs: largest weighted |residual|)
  double final_cost = 0;           // and at `parameters`
  double rms = 0;                  // unweighted RMS residual, in the fitted (transformed) space
  double max_abs = 0;              // largest |residual| there
  std::size_t rows = 0;
  int iterations = 0;
  std::string termination;  // "linear", "function tolerance", "no improving step", ...
  bool ok = true;
  std::string failure;  // why the fit failed (ok == false): the block keeps its start values
};

struct FixedFormSummary {
  std::vector<std::string> parameter_names;
  std::vector<ParameterScope> scopes;
  std::string solver;  // "linear least squares", "Levenberg-Marquardt", "... + Lawson minimax"
  bool linear = false;
  bool coupled = false;  // global and per-block parameters solved jointly
  std::vector<BlockResult> blocks;
  std::size_t failed_blocks = 0;
  double seconds = 0;

  // The value of a global parameter (the same in every block); nullopt for an unknown name.
  [[nodiscard]] std::optional<double> global(const std::string& name) const;
  // Solver, blocks fitted and failed, cost range, the global parameters (written as `print`
  // says) and the failed blocks.
  [[nodiscard]] std::string brief_report(
      const PrintOptions& print = PrintOptions::for_people()) const;
};

// Fits the problem. Throws shaderfit::Error, naming the problem, for: invalid options; a formula
// without free parameters; scopes of the wrong length; a transform with variables the formula
// lacks; a block whose columns do not match the formula or whose weights are negative or not
// finite (its label and row); a non-positive target under Loss::Log; a constraint that names an
// unknown parameter or lacks a variable's value; SolverKind::linear on a nonlinear problem; and,
// when there is a single block or every block fails the same way, a constraint that contradicts
// the others or a singular system (parameters the data and constraints do not determine).
// Otherwise failed blocks are reported in the summary (BlockResult::ok), never filled in.
void solve_fixed_form(const FixedFormOptions& options, const FixedFormProblem& problem,
                      FixedFormSummary* summary);

// The expression `outer` with every occurrence of its variable `name` replaced by `inner`; the
// result's variables are inner's followed by outer's others (shared names merged), its parameters
// inner's. Throws Error if outer has parameters.
Expression substitute_variable(const Expression& outer, const std::string& name,
                               const Expression& inner);

}  // namespace shaderfit
