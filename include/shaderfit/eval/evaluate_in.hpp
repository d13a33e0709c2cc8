// A formula evaluated in the shader's precision (expr/precision.hpp): the one definition of what
// "computed in half" means, used by the search, `eval`, the report and the tests
// (docs/precision.md):
//
//   std::vector<double> y(rows);
//   evaluate_in(Precision::Half, e, columns, y);  // every operation rounded to binary16
//
// In half, the inputs and every constant are rounded to binary16 first; then each operator of
// the expression takes half operands, is computed exactly (in float64, or to float64 accuracy for
// exp2, log2, sin, ...) and its result is rounded to the nearest binary16, ties to even, beyond
// 65504 to infinity, as numpy's float16 and cuda_fp16.h's __half arithmetic do. Compound
// operators round where the generated half code does: x^k after each multiplication of its
// squaring chain (apply_ipow), pow(a, b) = exp2(b * log2(a)) after each step; rsqrt, rcp and fma
// round once (hrsqrt, hrcp, __hfma).
#pragma once

#include <span>
#include <string_view>

#include "shaderfit/core.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/expr/precision.hpp"

namespace shaderfit {

// Evaluates e for out.size() rows in `p`, as evaluate() (eval/evaluate.hpp) takes its columns
// (one per e.variables entry; columns[i] may be null only when e does not read variable i) and
// throws. Double is evaluate() itself; Float rounds the inputs to float and evaluates in float.
void evaluate_in(Precision p, const Expression& e, std::span<const double* const> columns,
                 std::span<double> out);

// A half shader cannot hold a value beyond kHalfMax: throws Error located at `where` naming the
// first such value, "the target overflows half precision: 70000 in row 12 (half holds at most
// 65504)" (`what` = "the target"; rows counted from 1).
void check_fits_half(std::span<const double> values, std::string_view what,
                     const SourceLocation& where);

// One row in half, node by node, as evaluate_in(Precision::Half, ...).
double evaluate_half(const Expression& e, std::span<const double> variables);

}  // namespace shaderfit
