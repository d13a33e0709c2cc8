// Least squares with exact constraints (internal to src/rational), on the library's
// Levenberg-Marquardt solver (fit/least_squares.hpp).
//
// Minimises |r(x)|^2 subject to g(x) = 0. The constraints are met first, as least squares on g
// alone (Newton's method for g(x) = 0, damped); then the residuals are minimised on the
// constraints' tangent space, every step mapped back onto g = 0 by minimum-norm Newton steps
// (through the SVD of g's Jacobian). With no constraints this is plain Levenberg-Marquardt on r.
// Jacobians are central differences: the systems here have at most a few dozen unknowns and g
// and r are cheap.
#pragma once

#include <Eigen/Dense>
#include <functional>

namespace shaderfit::rational_detail {

struct NonlinearSystem {
  std::function<Eigen::VectorXd(const Eigen::VectorXd&)> constraints;  // g; may return size 0
  std::function<Eigen::VectorXd(const Eigen::VectorXd&)> residuals;    // r; may return size 0
};

struct NonlinearOutcome {
  Eigen::VectorXd x;
  bool converged = false;       // |g(x)| <= 1e-9 (1 + |x|)
  bool rank_deficient = false;  // the constraint Jacobian lost rank at the solution
  int iterations = 0;
  double constraint_norm = 0, residual_norm = 0;
  double condition_number = 0;  // of the constraint Jacobian at the solution (0 if none)
};

NonlinearOutcome nonlinear_least_squares(const NonlinearSystem& system, Eigen::VectorXd x0,
                                         int max_iterations = 100);

// min |A x - b| subject to E x = d (E may have no rows), by the null space of E.
Eigen::VectorXd constrained_least_squares(const Eigen::MatrixXd& a, const Eigen::VectorXd& b,
                                          const Eigen::MatrixXd& e, const Eigen::VectorXd& d);

}  // namespace shaderfit::rational_detail
