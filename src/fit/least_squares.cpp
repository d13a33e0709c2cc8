#include "shaderfit/fit/least_squares.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "shaderfit/core/error.hpp"

namespace shaderfit {

bool LeastSquaresOptions::is_valid(std::string* why) const {
  auto fail = [&](const char* m) {
    if (why != nullptr) *why = m;
    return false;
  };
  if (max_iterations < 1) return fail("LeastSquaresOptions::max_iterations must be at least 1");
  if (max_tries < 1) return fail("LeastSquaresOptions::max_tries must be at least 1");
  if (!(function_tolerance >= 0))
    return fail("LeastSquaresOptions::function_tolerance must not be negative");
  if (!(parameter_tolerance >= 0))
    return fail("LeastSquaresOptions::parameter_tolerance must not be negative");
  if (!(initial_lambda > 0)) return fail("LeastSquaresOptions::initial_lambda must be positive");
  if (!(min_lambda > 0)) return fail("LeastSquaresOptions::min_lambda must be positive");
  return true;
}

std::string_view termination_name(LeastSquaresTermination t) {
  switch (t) {
    case LeastSquaresTermination::max_iterations: return "max iterations";
    case LeastSquaresTermination::function_tolerance: return "function tolerance";
    case LeastSquaresTermination::parameter_tolerance: return "parameter tolerance";
    case LeastSquaresTermination::no_improving_step: return "no improving step";
    case LeastSquaresTermination::nonfinite_cost: return "non-finite cost";
    case LeastSquaresTermination::nonfinite_jacobian: return "non-finite jacobian";
    case LeastSquaresTermination::zero_cost: return "zero residual";
  }
  return "max iterations";
}

bool LeastSquaresProblem::step(std::span<const double> x, std::span<const double> dz,
                               std::vector<double>* trial, std::vector<double>* moved) {
  trial->resize(x.size());
  for (std::size_t k = 0; k < x.size(); ++k) (*trial)[k] = x[k] + dz[k];
  moved->assign(dz.begin(), dz.end());
  return true;
}

void levenberg_marquardt(const LeastSquaresOptions& o, LeastSquaresProblem& problem,
                         std::vector<double>* x, LeastSquaresSummary* summary) {
  using T = LeastSquaresTermination;
  std::string why;
  if (!o.is_valid(&why)) throw Error(why, {"LeastSquaresOptions"});
  LeastSquaresSummary s;
  LeastSquaresLinearization ne;
  problem.linearize(*x, &ne);
  double cost = std::isnan(ne.cost) ? problem.cost(*x) : ne.cost;
  s.initial_cost = cost;
  std::vector<double> trial, moved;
  double lambda = o.initial_lambda;
  s.termination = T::max_iterations;
  for (int it = 0; it < o.max_iterations; ++it) {
    s.iterations = it + 1;
    if (!std::isfinite(cost)) {
      s.termination = T::nonfinite_cost;
      break;
    }
    if (o.stop_at_zero_cost && cost == 0) {
      s.termination = T::zero_cost;
      break;
    }
    const auto n = static_cast<Eigen::Index>(ne.n);
    const Eigen::Map<const Eigen::MatrixXd> h(ne.h.data(), n, n);
    const Eigen::Map<const Eigen::VectorXd> g(ne.g.data(), n);
    if (!h.allFinite() || !g.allFinite()) {
      s.termination = T::nonfinite_jacobian;
      break;
    }
    bool improved = false;
    for (int tries = 0; tries < o.max_tries && !improved; ++tries) {
      Eigen::MatrixXd m = h;
      for (Eigen::Index k = 0; k < n; ++k) m(k, k) += lambda * std::max(h(k, k), 1e-12);
      const Eigen::VectorXd dz = m.ldlt().solve(-g);
      const bool feasible =
          problem.step(*x, std::span<const double>(dz.data(), dz.size()), &trial, &moved);
      const double trial_cost =
          feasible ? problem.cost(trial) : std::numeric_limits<double>::infinity();
      if (!(trial_cost < cost)) {
        lambda *= 10;
        continue;
      }
      double step = 0, size = 0;
      for (std::size_t k = 0; k < x->size(); ++k) {
        step += moved[k] * moved[k];
        size += (*x)[k] * (*x)[k];
      }
      const double decrease = (cost - trial_cost) / std::max(cost, 1e-300);
      x->swap(trial);
      cost = trial_cost;
      if (it + 1 < o.max_iterations) {
        problem.linearize(*x, &ne);  // for the next iteration
        if (!std::isnan(ne.cost)) cost = ne.cost;
      }
      lambda = std::max(lambda / 10, o.min_lambda);
      improved = true;
      if (decrease < o.function_tolerance)
        s.termination = T::function_tolerance;
      else if (std::sqrt(step) < o.parameter_tolerance * (std::sqrt(size) + o.parameter_tolerance))
        s.termination = T::parameter_tolerance;
    }
    if (!improved) {
      s.termination = T::no_improving_step;
      break;
    }
    if (s.termination != T::max_iterations) break;
  }
  s.final_cost = cost;
  *summary = s;
}

}  // namespace shaderfit
