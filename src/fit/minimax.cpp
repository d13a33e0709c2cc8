// Lawson's algorithm for the minimax loss, shared by the per-block and the joint solvers.
//
// With row weights u (sum 1), the weighted least-squares solution converges to the minimax one
// as each weight is multiplied by its row's residual: u_i <- u_i s_i / sum_j u_j s_j, where
// s_i = w_i |r_i| is the row's weighted residual. For a linear model sqrt(sum_i u_i s_i^2) never
// exceeds the minimax error, so the gap between it and the best max error found says when the
// iteration has converged.
#include <cmath>
#include <limits>

#include "fixed_form_internal.hpp"

namespace shaderfit::fit_detail {

Failure lawson(std::span<const double> w, int iterations, const LawsonSteps& steps,
               std::string* termination) {
  const std::size_t rows = w.size();
  std::vector<double> u(rows), eff(rows), s(rows);
  double count = 0;
  for (double wi : w) count += wi > 0 ? 1 : 0;
  for (std::size_t i = 0; i < rows; ++i) u[i] = w[i] > 0 ? 1 / count : 0;
  double best = std::numeric_limits<double>::infinity();
  bool converged = false;
  for (int k = 0; k < iterations; ++k) {
    for (std::size_t i = 0; i < rows; ++i) eff[i] = u[i] * w[i] * w[i];
    if (Failure f = steps.solve(eff)) return f;
    steps.residuals(&s);
    double error = 0, lower = 0, sum = 0;
    for (std::size_t i = 0; i < rows; ++i) {
      s[i] *= w[i];
      error = std::max(error, s[i]);
      lower += u[i] * s[i] * s[i];
      u[i] *= s[i];
      sum += u[i];
    }
    if (!std::isfinite(error)) break;  // e.g. a step into a pole: the best so far stays
    if (error < best) {
      best = error;
      steps.keep();
    }
    if (best - std::sqrt(lower) <= 1e-7 * best || !(sum > 0)) {
      converged = true;
      break;
    }
    for (double& x : u) x /= sum;
  }
  steps.restore();
  *termination = converged ? "minimax converged" : "minimax iterations";
  return {};
}

}  // namespace shaderfit::fit_detail
