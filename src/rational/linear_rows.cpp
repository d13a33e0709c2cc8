#include "rational/linear_rows.hpp"

#include <cmath>

#include "rational/quadrature.hpp"
#include "shaderfit/expr/forward.hpp"
#include "shaderfit/expr/jet.hpp"

namespace shaderfit::rational_detail {

using namespace shaderfit::rational;  // the area's public names

namespace {

double factorial(int k) {
  double f = 1;
  for (int i = 2; i <= k; ++i) f *= i;
  return f;
}

double binomial(int n, int k) {
  if (k < 0 || k > n) return 0.0;
  double r = 1;
  for (int i = 1; i <= k; ++i) r = r * (n - k + i) / i;
  return r;
}

// Integral over [a, b] in x of t^i.
double power_integral(const Transform& t, int i, double a, double b) {
  return (std::pow(t(b), i + 1) - std::pow(t(a), i + 1)) / ((i + 1) * t.scale);
}

Jet rational_jet(const Rational& r, double x0, int order) {
  const Jet x = Jet::variable(x0, order);
  const Jet t = Jet(r.form.variable.offset) + Jet(r.form.variable.scale) * x;
  auto horner = [&](const std::vector<double>& c) {
    Jet s(0.0);
    for (std::size_t i = c.size(); i-- > 0;) s = s * t + Jet(c[i]);
    return s;
  };
  return horner(r.p) / horner(r.q);
}

}  // namespace

double power_taylor(const Transform& t, int i, double x0, int k) {
  if (k > i) return 0.0;
  return binomial(i, k) * std::pow(t(x0), i - k) * std::pow(t.scale, k);
}

std::vector<ResolvedCondition> resolve_conditions(const RationalProblem& problem) {
  const std::vector<double> tp = problem.target_parameter_values();
  std::vector<ResolvedCondition> out;
  for (const Condition& c : problem.conditions) {
    ResolvedCondition r;
    r.source = &c;
    r.integral = c.is_integral();
    r.order = c.order;
    r.a = c.a;
    r.b = c.b;
    if (c.from_reference) {
      r.value = r.integral ? problem.target.integral(c.a, c.b, tp)
                           : problem.target.derivatives(c.a, c.order, tp).back();
    } else {
      r.value = evaluate_at(c.value, Jet(0.0), problem.parameter_values).value();
    }
    r.taylor = r.integral ? r.value : r.value / factorial(r.order);
    out.push_back(r);
  }
  return out;
}

std::optional<Eigen::RowVectorXd> linear_row(const RationalForm& form, const ResolvedCondition& c,
                                             std::span<const ResolvedCondition> all) {
  const int m = form.numerator_degree, n = form.denominator_degree;
  Eigen::RowVectorXd row = Eigen::RowVectorXd::Zero(m + n + 2);
  const Transform& t = form.variable;
  if (c.integral) {
    if (n > 0) return std::nullopt;
    for (int i = 0; i <= m; ++i) row(i) = power_integral(t, i, c.a, c.b);
    row(m + 1) = -c.taylor;
    return row;
  }
  const int k = c.order;
  // f_j for j in [k - n, k] at c.a, from the value conditions at that point.
  std::vector<std::optional<double>> f(static_cast<std::size_t>(k) + 1);
  for (const ResolvedCondition& o : all)
    if (!o.integral && o.a == c.a && o.order <= k) f[static_cast<std::size_t>(o.order)] = o.taylor;
  for (int j = std::max(0, k - n); j <= k; ++j)
    if (!f[static_cast<std::size_t>(j)]) return std::nullopt;
  for (int i = 0; i <= m; ++i) row(i) = power_taylor(t, i, c.a, k);
  // -(f Q)_k = -sum_j f_j [Q]_{k-j} with [Q]_{k-j} = sum_i q_i [t^i]_{k-j}.
  for (int i = 0; i <= n; ++i) {
    double s = 0;
    for (int j = std::max(0, k - i); j <= k; ++j)
      s += *f[static_cast<std::size_t>(j)] * power_taylor(t, i, c.a, k - j);
    row(m + 1 + i) = -s;
  }
  return row;
}

double condition_residual(const Rational& r, const ResolvedCondition& c) {
  // A fixed rule: Newton calls this for every Jacobian column, and a pole-free rational is
  // smooth; a rational with a pole near the interval is rejected afterwards anyway.
  if (c.integral) return integrate_fixed([&](double x) { return r(x); }, c.a, c.b) - c.taylor;
  return rational_jet(r, c.a, c.order).c[static_cast<std::size_t>(c.order)] - c.taylor;
}

Rational rational_from(const RationalForm& form, const Eigen::VectorXd& c) {
  Rational r;
  r.form = form;
  const int m = form.numerator_degree, n = form.denominator_degree;
  r.p.assign(c.data(), c.data() + m + 1);
  r.q.assign(static_cast<std::size_t>(n) + 1, 1.0);
  for (int i = 1; i <= n; ++i) r.q[static_cast<std::size_t>(i)] = c(m + i);
  return r;
}

Eigen::VectorXd coefficients_of(const Rational& r) {
  const int m = r.form.numerator_degree, n = r.form.denominator_degree;
  Eigen::VectorXd c(m + 1 + n);
  for (int i = 0; i <= m; ++i) c(i) = r.p[static_cast<std::size_t>(i)];
  for (int i = 1; i <= n; ++i) c(m + i) = r.q[static_cast<std::size_t>(i)];
  return c;
}

}  // namespace shaderfit::rational_detail
