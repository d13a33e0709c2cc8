// Formulas over data sets: parse a formula against a data set's column names, and evaluate it
// with its variables bound to the numeric columns of the same names.
//
//   Dataset d = read_csv("fresnel.csv");
//   Expression e = parse_formula_on("r0 + (x - r0) * x^4", d);
//   std::vector<double> r = evaluate_on(e, d);
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/eval/metrics.hpp"
#include "shaderfit/expr/expression.hpp"
#include "shaderfit/expr/precision.hpp"

namespace shaderfit {

struct Dataset;

// Parses `text` with the data set's column names as the known variables (so an unknown name is
// an error that lists the columns), then keeps only the variables the formula uses. Each used
// variable must be a numeric column (else shaderfit::Error at its first non-number cell).
// `source` names the formula in error locations.
Expression parse_formula_on(std::string_view text, const Dataset& data,
                            const std::string& source = "formula");

// Evaluates e on every row of `data`; its variables are looked up by name among the numeric
// columns (shaderfit::Error when one is missing or not numeric).
std::vector<double> evaluate_on(const Expression& e, const Dataset& data,
                                const EvalOptions& options = {});

// The same in `precision` (eval/evaluate_in.hpp: float rounds the inputs and computes in float,
// half rounds every operation to binary16), widened back.
std::vector<double> evaluate_on(const Expression& e, const Dataset& data, Precision precision);

// A formula's errors on a data set, overall and per group (what `shaderfit eval` reports).
struct EvalGroupResult {
  std::string column, label;
  ErrorMetrics metrics;
};

struct EvalFormulaResult {
  std::string input;    // as the user wrote it
  std::string formula;  // as shaderfit prints it (to_infix: constants exact)
  Expression expression;
  bool baseline = false;
  ErrorMetrics all;
  std::vector<EvalGroupResult> groups;  // per column of `groups`, its labels in sorted order
  // Where the data has a reference (problem/problem.hpp), set by the caller: the largest errors
  // found between the samples as well as at them (all.max_abs and all.max_rel are raised to
  // them; verify/worst_case.hpp), the domain point of the largest |error|, and a certified bound
  // (verify/certify.hpp) when asked for.
  bool checked_between_samples = false;
  std::vector<double> worst_point;
  std::optional<double> certified_max_abs;
  bool certified_converged = false;
  double certify_time_s = 0;
  std::string certify_note;  // why not converged, or why no finite bound
};

// Per-material inputs (cost/per_material.hpp) against the data: each must be a numeric column
// of `data`, and constant within every group of `groups` (rows with one value of a grouping
// column), as a material's inputs are. Throws Error located at "UniformInputs":
// "uniform input 'alpha' varies within group material=2 (0.1 in row 3, 0.3 in row 7)".
void check_uniform_in_groups(const Dataset& data, std::span<const std::string> uniform,
                             std::span<const std::string> groups);

// Parses `text` on `data` (parse_formula_on, errors located at `source`), evaluates it in
// `precision` (float64, or float32 or half as a shader would), and measures it against `target` on
// every row and on the rows of each value of each column in `groups` (numeric values by
// format_number).
EvalFormulaResult evaluate_formula_on(std::string_view text, const std::string& source,
                                      const Dataset& data, std::span<const double> target,
                                      std::span<const std::string> groups, Precision precision);

}  // namespace shaderfit
