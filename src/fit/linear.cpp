#include "shaderfit/fit/linear.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <limits>

#include "fit/fixed_form_internal.hpp"

namespace shaderfit {

LinearScaling fit_linear_scaling(std::span<const double> f, std::span<const double> y,
                                 std::span<const double> weights) {
  // Weighted means and (co)variances, two passes for accuracy.
  double sw = 0, mf = 0, my = 0;
  for (std::size_t i = 0; i < y.size(); ++i) {
    const double w = weights.empty() ? 1.0 : weights[i];
    if (!std::isfinite(f[i])) return {1.0, 0.0, std::numeric_limits<double>::infinity()};
    sw += w;
    mf += w * f[i];
    my += w * y[i];
  }
  if (!(sw > 0)) return {};
  mf /= sw;
  my /= sw;
  double sff = 0, sfy = 0;
  for (std::size_t i = 0; i < y.size(); ++i) {
    const double w = weights.empty() ? 1.0 : weights[i];
    const double df = f[i] - mf;
    sff += w * df * df;
    sfy += w * df * (y[i] - my);
  }
  LinearScaling s;
  s.a = sff > 0 ? sfy / sff : 0.0;
  s.b = my - s.a * mf;
  double se = 0;
  for (std::size_t i = 0; i < y.size(); ++i) {
    const double w = weights.empty() ? 1.0 : weights[i];
    const double d = s.a * f[i] + s.b - y[i];
    se += w * d * d;
  }
  s.mse = se / sw;
  return s;
}

std::vector<double> solve_least_squares(std::span<const double* const> columns,
                                        std::span<const double> y,
                                        std::span<const double> weights) {
  const auto rows = static_cast<Eigen::Index>(y.size());
  const auto k = static_cast<Eigen::Index>(columns.size());
  Eigen::MatrixXd a(rows, k);
  Eigen::VectorXd b(rows);
  for (Eigen::Index i = 0; i < rows; ++i) {
    const double sw = weights.empty() ? 1.0 : std::sqrt(weights[static_cast<std::size_t>(i)]);
    for (Eigen::Index j = 0; j < k; ++j) a(i, j) = sw * columns[static_cast<std::size_t>(j)][i];
    b(i) = sw * y[static_cast<std::size_t>(i)];
  }
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(a);
  const Eigen::VectorXd c = qr.solve(b);
  return {c.data(), c.data() + c.size()};
}

std::vector<double> solve_minimax_linear(std::span<const double* const> columns,
                                         std::span<const double> y, std::span<const double> weights,
                                         int iterations) {
  const std::size_t rows = y.size();
  std::vector<double> w(rows, 1.0);
  if (!weights.empty()) w.assign(weights.begin(), weights.end());
  std::vector<double> c, best;
  fit_detail::LawsonSteps steps;
  steps.solve = [&](std::span<const double> eff) {
    c = solve_least_squares(columns, y, eff);
    for (double v : c)
      if (!std::isfinite(v)) return fit_detail::Failure{fit_detail::FailureKind::nonfinite, ""};
    return fit_detail::Failure{};
  };
  steps.residuals = [&](std::vector<double>* r) {
    for (std::size_t i = 0; i < rows; ++i) {
      double g = 0;
      for (std::size_t j = 0; j < columns.size(); ++j) g += c[j] * columns[j][i];
      (*r)[i] = std::abs(g - y[i]);
    }
  };
  steps.keep = [&] { best = c; };
  steps.restore = [&] { c = best; };
  std::string termination;
  if (fit_detail::lawson(w, iterations, steps, &termination) || best.empty()) {
    // The first solve failed: the plain least-squares solution, as solve_least_squares gives it.
    return solve_least_squares(columns, y, weights);
  }
  return best;
}

}  // namespace shaderfit
