// Closed-form and linear least-squares fits.
//
//   LinearScaling s = fit_linear_scaling(f, y);      // best a * f + b, in closed form
//   double e = s.mse;
//   std::vector<double> c = solve_least_squares(design_columns, y);  // y ~ sum_j c_j column_j
//   std::vector<double> m = solve_minimax_linear(design_columns, y);  // the same, minimax
#pragma once

#include <span>
#include <vector>

namespace shaderfit {

struct LinearScaling {
  double a = 1.0;
  double b = 0.0;
  double mse = 0.0;  // weighted mean squared error of a * f + b
};

// The a and b minimising sum w (a f + b - y)^2 / sum w (weights empty: all 1): a = cov(f, y) /
// var(f), b = mean(y) - a mean(f), all weighted. When f is constant, a = 0 and b = mean(y).
// Non-finite f gives mse = +infinity.
LinearScaling fit_linear_scaling(std::span<const double> f, std::span<const double> y,
                                 std::span<const double> weights = {});

// The coefficients c minimising sum_i w_i (sum_j c_j columns[j][i] - y_i)^2, by a column-pivoting
// QR decomposition (Eigen), so rank-deficient designs give a least-squares solution with the
// redundant coefficients at 0. Every column has y.size() rows.
std::vector<double> solve_least_squares(std::span<const double* const> columns,
                                        std::span<const double> y,
                                        std::span<const double> weights = {});

// The coefficients c minimising max_i w_i |sum_j c_j columns[j][i] - y_i| (weights empty: all 1;
// rows of weight 0 do not count), by Lawson's reweighted least squares (the same iteration as
// solve_fixed_form's minimax) from the least-squares solution: at most `iterations` solves, the
// best coefficients seen returned. Every column has y.size() rows.
std::vector<double> solve_minimax_linear(std::span<const double* const> columns,
                                         std::span<const double> y,
                                         std::span<const double> weights = {}, int iterations = 60);

}  // namespace shaderfit
