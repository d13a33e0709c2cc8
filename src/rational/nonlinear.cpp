#include "rational/nonlinear.hpp"

#include <cmath>
#include <limits>

namespace shaderfit::rational::detail {

namespace {

constexpr double kMu = 1e8;  // weight of the constraints in the merit function

Eigen::VectorXd call(const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& f,
                     const Eigen::VectorXd& x) {
  return f ? f(x) : Eigen::VectorXd();
}

Eigen::MatrixXd jacobian(const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& f,
                         const Eigen::VectorXd& x, Eigen::Index rows) {
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

double merit(const Eigen::VectorXd& g, const Eigen::VectorXd& r) {
  const double m = kMu * g.squaredNorm() + r.squaredNorm();
  return std::isfinite(m) ? m : std::numeric_limits<double>::infinity();
}

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

NonlinearOutcome constrained_gauss_newton(const NonlinearSystem& sys, Eigen::VectorXd x,
                                          int max_iterations) {
  NonlinearOutcome out;
  const Eigen::Index n = x.size();
  Eigen::VectorXd g = call(sys.constraints, x), r = call(sys.residuals, x);
  double phi = merit(g, r);
  double lambda = 1e-6;
  for (int it = 0; it < max_iterations; ++it) {
    out.iterations = it + 1;
    const Eigen::MatrixXd jg = jacobian(sys.constraints, x, g.size());
    const Eigen::MatrixXd jr = jacobian(sys.residuals, x, r.size());
    Eigen::VectorXd step = Eigen::VectorXd::Zero(n);
    Eigen::MatrixXd z = Eigen::MatrixXd::Identity(n, n);
    if (g.size() > 0) {
      Eigen::JacobiSVD<Eigen::MatrixXd> svd(jg, Eigen::ComputeFullV | Eigen::ComputeThinU);
      const auto& s = svd.singularValues();
      Eigen::Index rank = 0;
      while (rank < s.size() && s(rank) > 1e-13 * s(0)) ++rank;
      for (Eigen::Index i = 0; i < rank; ++i)
        step -= svd.matrixV().col(i) * (svd.matrixU().col(i).dot(g) / s(i));
      z = svd.matrixV().rightCols(n - rank);
    }
    if (r.size() > 0 && z.cols() > 0) {
      const Eigen::MatrixXd a = jr * z;
      const Eigen::VectorXd b = -(r + jr * step);
      Eigen::MatrixXd normal = a.transpose() * a;
      normal.diagonal().array() += lambda * (1.0 + normal.diagonal().array());
      step += z * normal.ldlt().solve(a.transpose() * b);
    }
    // Backtrack until the merit decreases.
    double alpha = 1.0;
    bool accepted = false;
    Eigen::VectorXd xn, gn, rn;
    for (int k = 0; k < 40; ++k, alpha *= 0.5) {
      xn = x + alpha * step;
      gn = call(sys.constraints, xn);
      rn = call(sys.residuals, xn);
      const double phin = merit(gn, rn);
      if (phin < phi) {
        accepted = true;
        phi = phin;
        break;
      }
    }
    if (!accepted) {
      if (lambda < 1e6 && r.size() > 0) {
        lambda *= 100;
        continue;
      }
      break;
    }
    lambda = std::max(lambda / 10, 1e-12);
    const double moved = (alpha * step).norm();
    x = xn;
    g = gn;
    r = rn;
    if (moved <= 1e-14 * (1.0 + x.norm())) break;
  }
  out.x = x;
  out.constraint_norm = g.size() ? g.norm() : 0.0;
  out.residual_norm = r.size() ? r.norm() : 0.0;
  out.converged = out.constraint_norm <= 1e-9 * (1.0 + x.norm());
  if (g.size() > 0) {
    const Eigen::MatrixXd jg = jacobian(sys.constraints, x, g.size());
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(jg);
    const auto& s = svd.singularValues();
    out.condition_number =
        s(s.size() - 1) > 0 ? s(0) / s(s.size() - 1) : std::numeric_limits<double>::infinity();
    out.rank_deficient = g.size() >= n && s(s.size() - 1) <= 1e-12 * s(0);
  }
  return out;
}

}  // namespace shaderfit::rational::detail
