#include "rational/nonlinear.hpp"

#include <cmath>
#include <limits>
#include <span>
#include <vector>

#include "shaderfit/fit/least_squares.hpp"

namespace shaderfit::rational_detail {

namespace {

using Fn = std::function<Eigen::VectorXd(const Eigen::VectorXd&)>;

constexpr double kFeasible = 1e-9;  // |g| <= kFeasible (1 + |x|): the constraints are met

Eigen::VectorXd call(const Fn& f, const Eigen::VectorXd& x) { return f ? f(x) : Eigen::VectorXd(); }

Eigen::MatrixXd jacobian(const Fn& f, const Eigen::VectorXd& x, Eigen::Index rows) {
  Eigen::MatrixXd j(rows, x.size());
  if (rows == 0) return j;
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    const double h = 1e-6 * (1.0 + std::abs(x(i)));
    Eigen::VectorXd xp = x, xm = x;
    xp(i) += h;
    xm(i) -= h;
    j.col(i) = (f(xp) - f(xm)) / (2 * h);
  }
  return j;
}

// The SVD of g's Jacobian at x and its numerical rank.
struct ConstraintSvd {
  Eigen::JacobiSVD<Eigen::MatrixXd> svd;
  Eigen::Index rank = 0;
  ConstraintSvd(const Fn& g, const Eigen::VectorXd& x, Eigen::Index rows)
      : svd(jacobian(g, x, rows), Eigen::ComputeFullV | Eigen::ComputeThinU) {
    const auto& s = svd.singularValues();
    while (rank < s.size() && s(rank) > 1e-13 * s(0)) ++rank;
  }
};

// Minimum-norm Newton steps from *x onto g = 0; false when they end with the constraints unmet.
bool project(const Fn& g, Eigen::VectorXd* x) {
  Eigen::VectorXd gx = g(*x);
  for (int it = 0; it < 50 && gx.allFinite(); ++it) {
    if (gx.norm() <= 1e-12 * (1.0 + x->norm())) break;
    const ConstraintSvd c(g, *x, gx.size());
    Eigen::VectorXd step = Eigen::VectorXd::Zero(x->size());
    for (Eigen::Index i = 0; i < c.rank; ++i)
      step -= c.svd.matrixV().col(i) * (c.svd.matrixU().col(i).dot(gx) / c.svd.singularValues()(i));
    *x += step;
    gx = g(*x);
    if (step.norm() <= 1e-15 * (1.0 + x->norm())) break;
  }
  return gx.allFinite() && gx.norm() <= kFeasible * (1.0 + x->norm());
}

// |r(x)|^2 for the solver; with constraints g, on their tangent space with steps projected back.
class Residuals final : public LeastSquaresProblem {
 public:
  Residuals(const Fn& r, const Fn* g) : r_(r), g_(g) {}

  void linearize(std::span<const double> xs, LeastSquaresLinearization* out) override {
    const Eigen::Map<const Eigen::VectorXd> xm(xs.data(), static_cast<Eigen::Index>(xs.size()));
    const Eigen::VectorXd x = xm;
    const Eigen::VectorXd r = r_(x);
    const Eigen::Index n = x.size();
    z_ = Eigen::MatrixXd::Identity(n, n);
    if (g_ != nullptr) {
      const ConstraintSvd c(*g_, x, (*g_)(x).size());
      z_ = c.svd.matrixV().rightCols(n - c.rank);
    }
    const Eigen::MatrixXd a = jacobian(r_, x, r.size()) * z_;
    const Eigen::MatrixXd h = a.transpose() * a;
    const Eigen::VectorXd grad = a.transpose() * r;
    out->n = static_cast<std::size_t>(h.rows());
    out->h.assign(h.data(), h.data() + h.size());
    out->g.assign(grad.data(), grad.data() + grad.size());
  }

  double cost(std::span<const double> xs) override {
    const Eigen::VectorXd x =
        Eigen::Map<const Eigen::VectorXd>(xs.data(), static_cast<Eigen::Index>(xs.size()));
    const double c = r_(x).squaredNorm();
    return std::isfinite(c) ? c : std::numeric_limits<double>::infinity();
  }

  bool step(std::span<const double> xs, std::span<const double> dz, std::vector<double>* trial,
            std::vector<double>* moved) override {
    const Eigen::Map<const Eigen::VectorXd> x(xs.data(), static_cast<Eigen::Index>(xs.size()));
    Eigen::VectorXd t =
        x + z_ * Eigen::Map<const Eigen::VectorXd>(dz.data(), static_cast<Eigen::Index>(dz.size()));
    if (g_ != nullptr && !project(*g_, &t)) return false;
    trial->assign(t.data(), t.data() + t.size());
    moved->resize(xs.size());
    for (std::size_t j = 0; j < xs.size(); ++j) (*moved)[j] = (*trial)[j] - xs[j];
    return true;
  }

 private:
  const Fn& r_;
  const Fn* g_;
  Eigen::MatrixXd z_;
};

}  // namespace

Eigen::VectorXd constrained_least_squares(const Eigen::MatrixXd& a, const Eigen::VectorXd& b,
                                          const Eigen::MatrixXd& e, const Eigen::VectorXd& d) {
  const Eigen::Index n = a.cols();
  if (e.rows() == 0) return a.colPivHouseholderQr().solve(b);
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(e, Eigen::ComputeFullV | Eigen::ComputeThinU);
  const auto& s = svd.singularValues();
  Eigen::Index rank = 0;
  while (rank < s.size() && s(rank) > 1e-13 * s(0)) ++rank;
  Eigen::VectorXd xp = Eigen::VectorXd::Zero(n);
  for (Eigen::Index i = 0; i < rank; ++i)
    xp += svd.matrixV().col(i) * (svd.matrixU().col(i).dot(d) / s(i));
  if (rank == n || a.rows() == 0) return xp;
  const Eigen::MatrixXd z = svd.matrixV().rightCols(n - rank);
  const Eigen::VectorXd y = (a * z).colPivHouseholderQr().solve(b - a * xp);
  return xp + z * y;
}

NonlinearOutcome nonlinear_least_squares(const NonlinearSystem& sys, Eigen::VectorXd x,
                                         int max_iterations) {
  NonlinearOutcome out;
  const bool has_g = call(sys.constraints, x).size() > 0;
  const bool has_r = call(sys.residuals, x).size() > 0;
  LeastSquaresOptions lo;
  lo.max_iterations = max_iterations;
  lo.function_tolerance = 0;
  lo.parameter_tolerance = 1e-14;
  lo.initial_lambda = 1e-6;
  lo.stop_at_zero_cost = true;
  auto run = [&](const Fn& residuals, const Fn* constraints) {
    Residuals problem(residuals, constraints);
    std::vector<double> xs(x.data(), x.data() + x.size());
    LeastSquaresSummary summary;
    levenberg_marquardt(lo, problem, &xs, &summary);
    x = Eigen::Map<const Eigen::VectorXd>(xs.data(), x.size());
    out.iterations += summary.iterations;
  };
  if (has_g) run(sys.constraints, nullptr);
  if (has_r && (!has_g || project(sys.constraints, &x)))
    run(sys.residuals, has_g ? &sys.constraints : nullptr);
  const Eigen::VectorXd g = call(sys.constraints, x), r = call(sys.residuals, x);
  out.x = x;
  out.constraint_norm = g.size() ? g.norm() : 0.0;
  out.residual_norm = r.size() ? r.norm() : 0.0;
  out.converged = out.constraint_norm <= kFeasible * (1.0 + x.norm());
  if (g.size() > 0) {
    const Eigen::MatrixXd jg = jacobian(sys.constraints, x, g.size());
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(jg);
    const auto& s = svd.singularValues();
    out.condition_number =
        s(s.size() - 1) > 0 ? s(0) / s(s.size() - 1) : std::numeric_limits<double>::infinity();
    out.rank_deficient = g.size() >= x.size() && s(s.size() - 1) <= 1e-12 * s(0);
  }
  return out;
}

}  // namespace shaderfit::rational_detail
