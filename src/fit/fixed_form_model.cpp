// Evaluating the prepared model: fitted values and Jacobians per block, the loss, constraint rows,
// and projection of a parameter vector onto the constraints.
#include <algorithm>
#include <cmath>
#include <limits>

#include "fixed_form_internal.hpp"
#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/fit/fit.hpp"

namespace shaderfit::fit_detail {

LeastSquaresOptions lm_options(const FixedFormOptions& o) {
  LeastSquaresOptions lo;
  lo.max_iterations = o.max_iterations;
  lo.function_tolerance = o.function_tolerance;
  lo.parameter_tolerance = o.parameter_tolerance;
  lo.initial_lambda = o.initial_lambda;
  lo.min_lambda = 1e-15;
  lo.max_tries = 12;
  lo.stop_at_zero_cost = true;
  return lo;
}

void linearize(const Model& m, const PreparedBlock& b, std::span<const double> p,
               Linearization* out) {
  Expression e = m.fitted;
  e.parameter_values.assign(p.begin(), p.end());
  const std::size_t rows = b.rows();
  out->values.resize(rows);
  out->jacobian.resize(rows * p.size());
  evaluate_with_jacobian(e, b.columns, rows, out->values, out->jacobian);
}

void values(const Model& m, const PreparedBlock& b, std::span<const double> p,
            std::vector<double>* out) {
  Expression e = m.fitted;
  e.parameter_values.assign(p.begin(), p.end());
  out->resize(b.rows());
  if (b.rows() == 0) return;
  evaluate(e, std::span<const double* const>(b.columns), std::span<double>(*out));
}

double fit_cost(Loss loss, std::span<const double> v, std::span<const double> t,
                std::span<const double> w) {
  double acc = 0, sw = 0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (w[i] == 0) continue;
    const double r = v[i] - t[i];
    if (!std::isfinite(r)) return std::numeric_limits<double>::infinity();
    if (loss == Loss::MaxAbs) {
      acc = std::max(acc, w[i] * std::abs(r));
    } else {
      acc += w[i] * r * r;
      sw += w[i];
    }
  }
  if (loss == Loss::MaxAbs) return acc;
  return sw > 0 ? acc / sw : 0.0;
}

void residual_stats(const Model& m, const PreparedBlock& b, std::span<const double> p,
                    BlockResult* r) {
  std::vector<double> v;
  values(m, b, p, &v);
  double ss = 0, mx = 0;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const double d = std::abs(v[i] - b.target[i]);
    ss += d * d;
    mx = std::max(mx, std::isfinite(d) ? d : std::numeric_limits<double>::infinity());
  }
  r->rms = v.empty() ? 0.0 : std::sqrt(ss / static_cast<double>(v.size()));
  r->max_abs = mx;
  r->final_cost = fit_cost(m.loss == Loss::Log ? Loss::Mse : m.loss, v, b.target, b.weights);
}

namespace {

// f (and df/dp) at a constraint's point: one row through the forward-mode evaluator.
double point_value(const Expression& form, std::span<const double> point, std::span<const double> p,
                   std::span<double> gradient) {
  Expression e = form;
  e.parameter_values.assign(p.begin(), p.end());
  std::vector<const double*> columns(e.variables.size());
  for (std::size_t i = 0; i < columns.size(); ++i) columns[i] = &point[i];
  double v = 0;
  std::vector<double> jac(e.parameters.size());
  evaluate_with_jacobian(e, columns, 1, std::span<double>(&v, 1), jac);
  std::copy_n(jac.begin(), std::min(gradient.size(), jac.size()), gradient.begin());
  return v;
}

// df/dv at the point: the Jacobian column of the extra parameter that stands for v.
double derivative_value(const Model& m, const ConstraintInstance& c, std::span<const double> p) {
  const Expression& form = m.derivative_forms[c.index];
  const auto vi = static_cast<std::size_t>(
      std::find(m.formula.variables.begin(), m.formula.variables.end(), c.constraint->variable) -
      m.formula.variables.begin());
  std::vector<double> q(p.begin(), p.end());
  q.push_back(c.point[vi]);
  std::vector<double> g(q.size());
  point_value(form, c.point, q, g);
  return g.back();
}

}  // namespace

void constraint_row(const Model& m, const ConstraintInstance& c, std::span<const double> p,
                    double* value, std::span<double> gradient) {
  switch (c.constraint->kind) {
    case Constraint::Kind::parameters: {
      Expression e = c.constraint->lhs;
      e.parameter_values.assign(p.begin(), p.end());
      double v = 0;
      evaluate_with_jacobian(e, {}, 1, std::span<double>(&v, 1), gradient);
      *value = v - c.target;
      return;
    }
    case Constraint::Kind::value:
      *value = point_value(m.formula, c.point, p, gradient) - c.target;
      return;
    case Constraint::Kind::derivative: {
      *value = derivative_value(m, c, p) - c.target;
      // d(df/dv)/dp by central differences: exact (to rounding) when f is linear in p.
      std::vector<double> q(p.begin(), p.end());
      for (std::size_t j = 0; j < p.size(); ++j) {
        const double h = 1e-3 * std::max(1.0, std::abs(p[j]));
        q[j] = p[j] + h;
        const double up = derivative_value(m, c, q);
        q[j] = p[j] - h;
        const double down = derivative_value(m, c, q);
        q[j] = p[j];
        gradient[j] = (up - down) / (2 * h);
      }
      return;
    }
  }
}

Failure project(const Model& m, const PreparedBlock& b, const FixedFormOptions& o,
                std::vector<double>* p) {
  const std::size_t k = b.constraints.size(), n = p->size();
  if (k == 0) return {};
  Eigen::MatrixXd C(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(n));
  Eigen::VectorXd c(static_cast<Eigen::Index>(k));
  std::vector<double> grad(n);
  for (int it = 0; it < 50; ++it) {
    double worst = 0;
    for (std::size_t r = 0; r < k; ++r) {
      double v = 0;
      constraint_row(m, b.constraints[r], *p, &v, grad);
      c(static_cast<Eigen::Index>(r)) = v;
      for (std::size_t j = 0; j < n; ++j)
        C(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(j)) = grad[j];
      worst = std::max(worst, std::abs(v) / (1 + std::abs(b.constraints[r].target)));
      if (!std::isfinite(v)) worst = std::numeric_limits<double>::infinity();
    }
    if (worst <= o.constraint_tolerance) return {};
    if (!std::isfinite(worst) || !C.allFinite()) break;
    const Eigen::VectorXd dp = C.completeOrthogonalDecomposition().solve(-c);
    for (std::size_t j = 0; j < n; ++j) (*p)[j] += dp(static_cast<Eigen::Index>(j));
  }
  std::string names;
  for (const ConstraintInstance& ci : b.constraints)
    names += (names.empty() ? "'" : ", '") + ci.constraint->text + "'";
  return {FailureKind::contradiction, "the constraints " + names + " cannot all be met"};
}

}  // namespace shaderfit::fit_detail
