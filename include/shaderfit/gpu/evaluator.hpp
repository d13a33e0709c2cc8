// Batched evaluation of many formulas on a CUDA GPU, with the loss reduced on the device so that
// only a few sums per formula come back (docs/gpu.md).
//
//   GpuEvaluator gpu(columns, target);  // data uploaded once: inputs as float32, target as is
//   std::vector<const Expression*> population = ...;  // over the same variables, in order
//   std::vector<PopulationScore> s = gpu.evaluate_population(population, Loss::Mse);
//   LinearScaling ab = s[0].linear_scaling();      // the best a * f + b, from the sums
//   auto scaled = gpu.evaluate_population(population, Loss::Mse, {&ab, 1});  // ...its loss
//
// Formulas are evaluated in float32 with the semantics of expr/op.hpp (as a shader would); the
// sums are accumulated in float64. Results match the CPU path within float32 tolerance
// (docs/gpu.md gives it) and do not depend on the batch a formula is evaluated in.
// Throws shaderfit::Error when cuda_available() is false, so a build without CUDA compiles
// callers unchanged. Calls from several threads are serialised.
#pragma once

#include <cstddef>
#include <memory>
#include <span>
#include <vector>

#include "shaderfit/eval/loss.hpp"
#include "shaderfit/expr/expression.hpp"
#include "shaderfit/fit/linear.hpp"

namespace shaderfit {

struct PopulationScore {
  // loss_of(kind, a * f + b, target, weights), with a, b from the scaling passed (default 1, 0):
  // +infinity when a prediction is not finite.
  double loss = 0;
  bool finite = true;  // every prediction (rows with weight > 0) finite
  // Weighted moments over the rows with weight > 0 of the formula f itself (when finite):
  // sum w, the means of f and y, sff = sum w (f - mean_f)^2, sfy = sum w (f - mean_f)(y - mean_y),
  // and the data's syy = sum w (y - mean_y)^2.
  double sum_w = 0, mean_f = 0, mean_y = 0, sff = 0, sfy = 0, syy = 0;

  // fit_linear_scaling's a and b from the moments (a = 0 when f is constant), and its weighted
  // mse, (a^2 sff - 2 a sfy + syy) / sum w (for an exact loss of a near-perfect fit, evaluate
  // the scaled formula). mse = +infinity when f is not finite.
  [[nodiscard]] LinearScaling linear_scaling() const;
};

// Normal equations of a fit of y - g0 by sum_j c_j g_j: jtj[i * k + j] = sum w g_i g_j,
// jtr[i] = sum w g_i (y - g0), rr = sum w (y - g0)^2 (rows with weight > 0).
struct NormalEquations {
  std::size_t k = 0;
  std::vector<double> jtj, jtr;
  double rr = 0, sum_w = 0;
  bool finite = true;  // every basis value finite
};

class GpuEvaluator {
 public:
  // columns[i] holds target.size() values of variable i. Throws Error when CUDA is unavailable,
  // for no columns, fewer than 1 row, a null column, or weights of another length.
  GpuEvaluator(std::span<const double* const> columns, std::span<const double> target,
               std::span<const double> weights = {});
  ~GpuEvaluator();
  GpuEvaluator(GpuEvaluator&&) noexcept;
  GpuEvaluator& operator=(GpuEvaluator&&) noexcept;

  [[nodiscard]] std::size_t rows() const;
  [[nodiscard]] std::size_t columns() const;

  // One score per formula, in order. Each formula must have columns() variables, parameter
  // values for its parameters, and a postfix stack depth of at most 32 (every formula of up to
  // 63 nodes has); otherwise Error.
  // `scaling` is empty or has one entry per formula (only a and b are read).
  [[nodiscard]] std::vector<PopulationScore> evaluate_population(
      std::span<const Expression* const> population, Loss loss,
      std::span<const LinearScaling> scaling = {}) const;

  // The normal equations of a fit linear in its coefficients; 1 <= basis.size() <= 8.
  [[nodiscard]] NormalEquations normal_equations(std::span<const Expression* const> basis,
                                                 const Expression* offset = nullptr) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace shaderfit
