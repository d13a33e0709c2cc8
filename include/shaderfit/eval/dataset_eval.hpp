// Formulas over data sets: parse a formula against a data set's column names, and evaluate it
// with its variables bound to the numeric columns of the same names.
//
//   Dataset d = read_csv("fresnel.csv");
//   Expression e = parse_formula_on("r0 + (x - r0) * x^4", d);
//   std::vector<double> r = evaluate_on(e, d);
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/expr/expression.hpp"

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
std::vector<double> evaluate_on(const Expression& e, const Dataset& data, const EvalOptions& options = {});

// The same in float32: inputs rounded to float, evaluated in float, widened back.
std::vector<double> evaluate_on_f32(const Expression& e, const Dataset& data,
                                    const EvalOptions& options = {});

}  // namespace shaderfit
