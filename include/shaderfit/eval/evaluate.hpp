// Batched CPU evaluation of one expression over many rows.
//
//   // e over variables {"r0", "x"}; columns[i] holds e.variables[i] for every row.
//   std::vector<float> r0 = ..., x = ..., out(x.size());
//   const float* columns[] = {r0.data(), x.data()};
//   shaderfit::evaluate(e, columns, out);                  // all cores
//   shaderfit::evaluate(e, columns, out, {.threads = 1});  // this thread only
//
// The values are those of apply_unary / apply_binary / apply_ipow / apply_fma (expr/op.hpp)
// computed in the column type: arithmetic ops (+ - * / min max neg abs saturate ipow fma sqrt
// rsqrt rcp) give the same bits as those functions; exp2 exp log2 log sin cos pow are SIMD
// approximations within a few ulp of them, with the same special values (docs/evaluation.md).
// A row's result depends only on that row, so it is the same for every thread count.
#pragma once

#include <cstddef>
#include <span>

#include "shaderfit/core.hpp"

namespace shaderfit {

struct EvalOptions {
  // Threads to use, the calling thread included; 0 = std::thread::hardware_concurrency().
  int threads = 0;
  // Rows are split into tasks of at least this many rows; fewer rows run on the caller.
  std::size_t min_rows_per_task = 16384;
};

// Evaluates `e` for out.size() rows: columns[i] points to the out.size() values of
// e.variables[i], and Param nodes read e.parameter_values. Throws shaderfit::Error if
// columns.size() != e.variables.size(), a column the expression reads is null, options.threads
// is negative, or the expression is malformed (not one postfix tree, an unknown op, a variable
// or parameter index out of range, or an IPow exponent outside [-16, 16]).
void evaluate(const Expression& e, std::span<const float* const> columns, std::span<float> out,
              const EvalOptions& options = {});
void evaluate(const Expression& e, std::span<const double* const> columns, std::span<double> out,
              const EvalOptions& options = {});

// One row in double precision, node by node: the reference semantics the batched evaluators
// are tested against. `variables` holds one value per e.variables entry; throws as evaluate().
double evaluate_scalar(const Expression& e, std::span<const double> variables);

}  // namespace shaderfit
