// The nonlinear least-squares solver: Levenberg-Marquardt on the normal equations, in the
// Options + Problem + Summary style. Every nonlinear fit in shaderfit runs this one loop: the
// search's constant fitting (fit_parameters), the fixed-form block and coupled solvers and
// rational's constrained fits.
//
// The problem supplies, per iteration, the normal equations of its linearised weighted residuals
// (H = J^T W J, g = J^T W r, in whatever coordinates its steps live: all parameters, the free ones,
// the constraints' tangent space) and, per trial, the cost and the point a step leads to (x + dz
// by default; a problem with constraints maps dz back and projects). The loop:
//   solve (H + lambda diag(max(H_kk, 1e-12))) dz = -g; take the trial if its cost is lower
//   (lambda /= 10, not below min_lambda; then re-linearise), else lambda *= 10 and try again,
//   at most max_tries times per iteration.
// It stops on a relative cost decrease below function_tolerance, a step with
// |step| < parameter_tolerance (|x| + parameter_tolerance), no improving step, a non-finite cost
// or normal equations, a zero cost (when asked) or after max_iterations.
#pragma once

#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace shaderfit {

struct LeastSquaresOptions {
  int max_iterations = 50;
  double function_tolerance = 1e-10;   // relative cost decrease of an accepted step; 0: never
  double parameter_tolerance = 1e-10;  // step length relative to the parameters; 0: never
  double initial_lambda = 1e-3;        // damping, relative to the diagonal of H
  double min_lambda = 1e-12;           // damping never falls below this
  int max_tries = 10;                  // damping increases per iteration before giving up
  bool stop_at_zero_cost = false;      // an exact fit ends the iterations

  // False, with the reason in *why, for max_iterations or max_tries < 1, a negative tolerance
  // or a lambda <= 0.
  bool is_valid(std::string* why) const;
};

enum class LeastSquaresTermination : std::uint8_t {
  max_iterations,
  function_tolerance,
  parameter_tolerance,
  no_improving_step,
  nonfinite_cost,
  nonfinite_jacobian,
  zero_cost,
};

// "max iterations", "function tolerance", "parameter tolerance", "no improving step",
// "non-finite cost", "non-finite jacobian", "zero residual".
std::string_view termination_name(LeastSquaresTermination t);

// The normal equations of the linearised problem at x, in the step's coordinates (n of them).
struct LeastSquaresLinearization {
  std::size_t n = 0;
  std::vector<double> h;  // n x n, column-major: J^T W J
  std::vector<double> g;  // n: J^T W r
  // The cost at x where the linearisation computes it (it then replaces the cost of the accepted
  // trial); NaN keeps the trial's.
  double cost = std::numeric_limits<double>::quiet_NaN();
};

class LeastSquaresProblem {
 public:
  virtual ~LeastSquaresProblem() = default;
  // The normal equations at x.
  virtual void linearize(std::span<const double> x, LeastSquaresLinearization* out) = 0;
  // The cost at x (a trial point); +inf or NaN when not finite.
  virtual double cost(std::span<const double> x) = 0;
  // The trial point for the step dz (normal-equation coordinates) from x, and `moved`, the step
  // in x's coordinates whose length the parameter tolerance tests. False: no feasible point
  // (the trial is rejected). By default trial = x + dz, moved = dz.
  virtual bool step(std::span<const double> x, std::span<const double> dz,
                    std::vector<double>* trial, std::vector<double>* moved);
};

struct LeastSquaresSummary {
  double initial_cost = 0;  // as the first linearisation (or cost) computed it
  double final_cost = 0;
  int iterations = 0;
  LeastSquaresTermination termination = LeastSquaresTermination::max_iterations;
};

// Minimises the problem's cost from *x (updated in place). Throws shaderfit::Error for invalid
// options.
void levenberg_marquardt(const LeastSquaresOptions& options, LeastSquaresProblem& problem,
                         std::vector<double>* x, LeastSquaresSummary* summary);

}  // namespace shaderfit
