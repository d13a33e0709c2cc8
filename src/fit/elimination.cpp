// Constraint elimination and rank-checked least-squares solves.
#include <algorithm>
#include <cmath>

#include "fixed_form_internal.hpp"

namespace shaderfit::fit_detail {

namespace {

using Index = Eigen::Index;

std::string quoted_list(std::span<const std::string> names, const std::vector<std::size_t>& which) {
  std::string s;
  for (std::size_t i = 0; i < which.size(); ++i) {
    if (i > 0) s += i + 1 == which.size() ? " and " : ", ";
    s += "'" + names[which[i]] + "'";
  }
  return s;
}

Failure singular(std::span<const std::string> names, const std::vector<std::size_t>& which) {
  const bool one = which.size() == 1;
  return {FailureKind::singular,
          std::string("singular system: the data and constraints do not determine ") +
              (one ? "parameter " : "parameters ") + quoted_list(names, which) +
              (one ? " (its effect is zero or a combination of the other parameters')"
                   : " (their effects are zero or combinations of the other parameters')")};
}

}  // namespace

Failure eliminate(const Eigen::MatrixXd& C, const Eigen::VectorXd& d,
                  std::span<const std::string> row_names, double tolerance, Elimination* out) {
  const Index n = C.cols();
  struct Row {
    Eigen::RowVectorXd u;  // 1 at `pivot`, 0 at every other row's pivot
    double s;
    Index pivot;
  };
  std::vector<Row> rows;
  std::vector<std::size_t> seen;  // constraints kept or redundant so far, for messages
  for (Index r = 0; r < C.rows(); ++r) {
    Eigen::RowVectorXd v = C.row(r);
    double rhs = d(r);
    const double scale = v.cwiseAbs().maxCoeff();
    for (const Row& row : rows) {
      const double coef = v(row.pivot);
      if (coef != 0) {
        v -= coef * row.u;
        rhs -= coef * row.s;
      }
    }
    Index pivot = 0;
    const double largest = n > 0 ? v.cwiseAbs().maxCoeff(&pivot) : 0.0;
    if (!(largest > tolerance * scale) || scale == 0) {
      if (std::abs(rhs) > tolerance * (1 + std::abs(d(r)))) {
        const std::string& name = row_names[static_cast<std::size_t>(r)];
        if (seen.empty() || scale == 0)
          return {FailureKind::contradiction,
                  "constraint '" + name + "' cannot be met: it does not depend on the parameters"};
        std::vector<std::string> names(row_names.begin(), row_names.end());
        return {FailureKind::contradiction,
                "constraint '" + name + "' contradicts " + quoted_list(names, seen)};
      }
      seen.push_back(static_cast<std::size_t>(r));
      continue;  // redundant
    }
    seen.push_back(static_cast<std::size_t>(r));
    Row fresh{v / v(pivot), rhs / v(pivot), pivot};
    fresh.u(pivot) = 1.0;
    for (Row& row : rows) {
      const double coef = row.u(pivot);
      if (coef != 0) {
        row.u -= coef * fresh.u;
        row.s -= coef * fresh.s;
        row.u(pivot) = 0.0;
      }
    }
    rows.push_back(std::move(fresh));
  }
  std::vector<bool> is_pivot(static_cast<std::size_t>(n), false);
  for (const Row& row : rows) is_pivot[static_cast<std::size_t>(row.pivot)] = true;
  out->free.clear();
  for (Index j = 0; j < n; ++j)
    if (!is_pivot[static_cast<std::size_t>(j)]) out->free.push_back(static_cast<int>(j));
  const auto nf = static_cast<Index>(out->free.size());
  out->p0 = Eigen::VectorXd::Zero(n);
  out->Z = Eigen::MatrixXd::Zero(n, nf);
  for (Index q = 0; q < nf; ++q) out->Z(out->free[static_cast<std::size_t>(q)], q) = 1.0;
  for (const Row& row : rows) {
    out->p0(row.pivot) = row.s;
    for (Index q = 0; q < nf; ++q) {
      const double u = row.u(out->free[static_cast<std::size_t>(q)]);
      if (u != 0) out->Z(row.pivot, q) = -u;
    }
  }
  return {};
}

Failure solve_design(const Eigen::MatrixXd& A, const Eigen::VectorXd& b,
                     std::span<const std::string> column_names, double rank_tolerance,
                     Eigen::VectorXd* q) {
  const Index n = A.cols();
  *q = Eigen::VectorXd::Zero(n);
  if (n == 0) return {};
  if (!A.allFinite() || !b.allFinite())
    return {FailureKind::nonfinite, "the fitted values or their derivatives are not finite"};
  Eigen::VectorXd norm = A.colwise().norm().transpose();
  std::vector<std::size_t> zero;
  for (Index j = 0; j < n; ++j)
    if (!(norm(j) > 0)) zero.push_back(static_cast<std::size_t>(j));
  if (!zero.empty()) return singular(column_names, zero);
  const Eigen::MatrixXd scaled = A * norm.cwiseInverse().asDiagonal();
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(scaled);
  qr.setThreshold(rank_tolerance);
  if (qr.rank() < n) {
    std::vector<std::size_t> dependent;
    for (Index k = qr.rank(); k < n; ++k)
      dependent.push_back(static_cast<std::size_t>(qr.colsPermutation().indices()(k)));
    std::sort(dependent.begin(), dependent.end());
    return singular(column_names, dependent);
  }
  *q = norm.cwiseInverse().asDiagonal() * qr.solve(b);
  if (!q->allFinite()) return {FailureKind::nonfinite, "the least-squares solution is not finite"};
  return {};
}

Failure solve_normal(const Eigen::MatrixXd& H, const Eigen::VectorXd& rhs,
                     std::span<const std::string> column_names, double rank_tolerance,
                     Eigen::VectorXd* q) {
  const Index n = H.rows();
  *q = Eigen::VectorXd::Zero(n);
  if (n == 0) return {};
  if (!H.allFinite() || !rhs.allFinite())
    return {FailureKind::nonfinite, "the fitted values or their derivatives are not finite"};
  Eigen::VectorXd s(n);
  std::vector<std::size_t> zero;
  for (Index j = 0; j < n; ++j) {
    if (!(H(j, j) > 0)) zero.push_back(static_cast<std::size_t>(j));
    s(j) = H(j, j) > 0 ? 1 / std::sqrt(H(j, j)) : 1.0;
  }
  if (!zero.empty()) return singular(column_names, zero);
  const Eigen::MatrixXd scaled = s.asDiagonal() * H * s.asDiagonal();
  Eigen::LDLT<Eigen::MatrixXd> ldlt(scaled);
  const Eigen::VectorXd D = ldlt.vectorD();
  const double threshold =
      std::max(rank_tolerance * rank_tolerance, 1e-13) * D.cwiseAbs().maxCoeff();
  Eigen::VectorXi order = Eigen::VectorXi::LinSpaced(n, 0, static_cast<int>(n - 1));
  order = ldlt.transpositionsP() * order;
  std::vector<std::size_t> dependent;
  for (Index k = 0; k < n; ++k)
    if (!(D(k) > threshold)) dependent.push_back(static_cast<std::size_t>(order(k)));
  if (!dependent.empty()) {
    std::sort(dependent.begin(), dependent.end());
    return singular(column_names, dependent);
  }
  *q = s.asDiagonal() * ldlt.solve(s.asDiagonal() * rhs);
  if (!q->allFinite()) return {FailureKind::nonfinite, "the least-squares solution is not finite"};
  return {};
}

}  // namespace shaderfit::fit_detail
