// Least squares with exact constraints, by Gauss-Newton (internal to src/rational).
//
// Minimises |r(x)|^2 subject to g(x) = 0. Each step satisfies the linearised constraints exactly
// (minimum-norm step through the SVD of their Jacobian) and spends the remaining freedom on the
// linearised residuals (Levenberg-Marquardt damped), then backtracks along the step until the
// merit mu |g|^2 + |r|^2 decreases. With no residuals this is Newton's method for g(x) = 0; with
// no constraints, Gauss-Newton. Jacobians are central differences: the systems here have at most
// a few dozen unknowns and g and r are cheap.
#pragma once

#include <Eigen/Dense>
#include <functional>

namespace shaderfit::rational::detail {

struct NonlinearSystem {
  std::function<Eigen::VectorXd(const Eigen::VectorXd&)> constraints;  // g; may return size 0
  std::function<Eigen::VectorXd(const Eigen::VectorXd&)> residuals;    // r; may return size 0
};

struct NonlinearOutcome {
  Eigen::VectorXd x;
  bool converged = false;
  bool rank_deficient = false;  // the constraint Jacobian lost rank at the solution
  int iterations = 0;
  double constraint_norm = 0, residual_norm = 0;
  double condition_number = 0;  // of the constraint Jacobian at the solution (0 if none)
};

NonlinearOutcome constrained_gauss_newton(const NonlinearSystem& system, Eigen::VectorXd x0,
                                          int max_iterations = 100);

// min |A x - b| subject to E x = d (E may have no rows), by the null space of E.
Eigen::VectorXd constrained_least_squares(const Eigen::MatrixXd& a, const Eigen::VectorXd& b,
                                          const Eigen::MatrixXd& e, const Eigen::VectorXd& d);

}  // namespace shaderfit::rational::detail
