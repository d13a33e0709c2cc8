#include "shaderfit/fit/fit.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <limits>

#include "fixed_form_internal.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/fit/least_squares.hpp"
#include "shaderfit/fit/linear.hpp"

namespace shaderfit {

namespace {

double weighted_mse(std::span<const double> f, std::span<const double> y,
                    std::span<const double> w) {
  double se = 0, sw = 0;
  for (std::size_t i = 0; i < y.size(); ++i) {
    const double wi = w.empty() ? 1.0 : w[i];
    const double d = f[i] - y[i];
    se += wi * d * d;
    sw += wi;
  }
  const double m = sw > 0 ? se / sw : 0.0;
  return std::isfinite(m) ? m : std::numeric_limits<double>::infinity();
}

struct Evaluation {
  std::vector<double> values, jacobian;
  double cost = 0;
};

void evaluate(const FitProblem& p, const Expression& e, Evaluation& out) {
  const std::size_t rows = p.target.size();
  out.values.resize(rows);
  out.jacobian.resize(rows * e.parameters.size());
  evaluate_with_jacobian(e, p.columns, rows, out.values, out.jacobian);
  out.cost = weighted_mse(out.values, p.target, p.weights);
}

// Values only (a trial step): the batched evaluator, no derivatives.
double cost_at(const FitProblem& p, const Expression& e, std::vector<double>& values) {
  values.resize(p.target.size());
  shaderfit::evaluate(e, p.columns, values, {.threads = 1});
  return weighted_mse(values, p.target, p.weights);
}

// f(p) = f(0) + J p exactly for a linear formula: one weighted least-squares solve.
void fit_linear(const FitProblem& p, Expression& e, FitSummary* s) {
  const std::size_t rows = p.target.size(), np = e.parameters.size();
  const std::vector<double> start = e.parameter_values;
  std::fill(e.parameter_values.begin(), e.parameter_values.end(), 0.0);
  Evaluation at_zero;
  evaluate(p, e, at_zero);
  std::vector<double> rhs(rows);
  for (std::size_t i = 0; i < rows; ++i) rhs[i] = p.target[i] - at_zero.values[i];
  std::vector<const double*> cols(np);
  for (std::size_t j = 0; j < np; ++j) cols[j] = at_zero.jacobian.data() + j * rows;
  std::vector<double> c = solve_least_squares(cols, rhs, p.weights);
  bool finite = true;
  for (double v : c) finite = finite && std::isfinite(v);
  e.parameter_values = finite ? c : start;
  std::vector<double> values;
  double cost = cost_at(p, e, values);
  if (!(cost <= s->initial_cost)) {  // e.g. NaN rows: keep the start
    e.parameter_values = start;
    cost = s->initial_cost;
  }
  s->parameters = e.parameter_values;
  s->final_cost = cost;
  s->linear = true;
  s->iterations = 1;
  s->termination = "linear";
}

// The weighted residuals f(p) - y of the formula. The cost of a linearisation is computed from
// the values of the Jacobian's evaluator, that of a trial from the value evaluator.
class FitResiduals final : public LeastSquaresProblem {
 public:
  FitResiduals(const FitProblem& p, Expression& e) : p_(p), e_(e) {}

  void linearize(std::span<const double> x, LeastSquaresLinearization* out) override {
    const std::size_t rows = p_.target.size(), np = e_.parameters.size();
    const auto n = static_cast<Eigen::Index>(np);
    e_.parameter_values.assign(x.begin(), x.end());
    evaluate(p_, e_, cur_);
    // Normal equations of the weighted problem: J^T W J and J^T W r.
    const Eigen::Map<const Eigen::MatrixXd> jac(cur_.jacobian.data(),
                                                static_cast<Eigen::Index>(rows), n);
    residual_.resize(static_cast<Eigen::Index>(rows));
    for (std::size_t i = 0; i < rows; ++i) residual_[i] = cur_.values[i] - p_.target[i];
    if (p_.weights.empty()) {
      jtj_.noalias() = jac.transpose() * jac;
      jtr_.noalias() = jac.transpose() * residual_;
    } else {
      const Eigen::Map<const Eigen::VectorXd> w(p_.weights.data(), static_cast<Eigen::Index>(rows));
      weighted_ = jac.array().colwise() * w.array();
      jtj_.noalias() = weighted_.transpose() * jac;
      jtr_.noalias() = weighted_.transpose() * residual_;
    }
    out->n = np;
    out->h.assign(jtj_.data(), jtj_.data() + jtj_.size());
    out->g.assign(jtr_.data(), jtr_.data() + jtr_.size());
    out->cost = cur_.cost;
  }

  double cost(std::span<const double> x) override {
    e_.parameter_values.assign(x.begin(), x.end());
    return cost_at(p_, e_, trial_values_);
  }

 private:
  const FitProblem& p_;
  Expression& e_;
  Evaluation cur_;
  std::vector<double> trial_values_;
  Eigen::VectorXd residual_, jtr_;
  Eigen::MatrixXd weighted_, jtj_;
};

void fit_levenberg_marquardt(const FitOptions& o, const FitProblem& p, Expression& e,
                             FitSummary* s) {
  LeastSquaresOptions lo;
  lo.max_iterations = o.max_iterations;
  lo.function_tolerance = o.function_tolerance;
  lo.parameter_tolerance = o.parameter_tolerance;
  lo.initial_lambda = o.initial_lambda;
  FitResiduals residuals(p, e);
  std::vector<double> x = e.parameter_values;
  LeastSquaresSummary ls;
  levenberg_marquardt(lo, residuals, &x, &ls);
  e.parameter_values = x;
  s->parameters = std::move(x);
  s->final_cost = ls.final_cost;
  s->iterations = ls.iterations;
  s->termination = termination_name(ls.termination);
}

double max_error(const FitProblem& p, const Expression& e, std::vector<double>& values) {
  values.resize(p.target.size());
  shaderfit::evaluate(e, p.columns, values, {.threads = 1});
  double m = 0;
  for (std::size_t i = 0; i < values.size(); ++i) {
    const double wi = p.weights.empty() ? 1.0 : p.weights[i];
    if (wi == 0) continue;
    const double d = wi * std::abs(values[i] - p.target[i]);
    if (!(d <= m)) m = std::isnan(d) ? std::numeric_limits<double>::infinity() : d;
  }
  return m;
}

// One least-squares fit of e (from its values) with the problem's rows and the given weights.
void least_squares(const FitOptions& o, const FitProblem& p, bool linear, Expression& e,
                   FitSummary* s) {
  std::vector<double> values;
  s->initial_cost = cost_at(p, e, values);
  s->final_cost = s->initial_cost;
  s->parameters = e.parameter_values;
  if (linear)
    fit_linear(p, e, s);
  else
    fit_levenberg_marquardt(o, p, e, s);
}

// Lawson's reweighting (fit_detail::lawson) around least_squares.
void fit_minimax(const FitOptions& o, const FitProblem& p, bool linear, Expression& e,
                 FitSummary* s) {
  std::vector<double> w(p.target.size(), 1.0), values;
  if (!p.weights.empty()) w.assign(p.weights.begin(), p.weights.end());
  const std::vector<double> start = e.parameter_values;
  std::vector<double> best = start;
  FitProblem pass = p;
  int iterations = 0;
  fit_detail::LawsonSteps steps;
  steps.solve = [&](std::span<const double> eff) {
    pass.weights = eff;
    FitSummary t;
    least_squares(o, pass, linear, e, &t);
    iterations += t.iterations;
    ++s->minimax_passes;
    return fit_detail::Failure{};
  };
  steps.residuals = [&](std::vector<double>* r) {
    values.resize(p.target.size());
    shaderfit::evaluate(e, p.columns, values, {.threads = 1});
    for (std::size_t i = 0; i < values.size(); ++i) (*r)[i] = std::abs(values[i] - p.target[i]);
  };
  steps.keep = [&] { best = e.parameter_values; };
  steps.restore = [&] { e.parameter_values = best; };
  fit_detail::lawson(w, o.minimax_iterations, steps, &s->termination);
  double cost = max_error(p, e, values);
  if (!(cost < s->initial_cost)) {
    e.parameter_values = start;
    cost = s->initial_cost;
  }
  s->parameters = e.parameter_values;
  s->final_cost = cost;
  s->iterations = iterations;
  s->linear = linear;
}

}  // namespace

bool FitOptions::is_valid(std::string* why) const {
  auto fail = [&](const char* m) {
    if (why != nullptr) *why = m;
    return false;
  };
  if (max_iterations < 1) return fail("max_iterations must be at least 1");
  if (minimax_iterations < 1) return fail("minimax_iterations must be at least 1");
  if (!(function_tolerance > 0) || !(parameter_tolerance > 0))
    return fail("tolerances must be positive");
  if (!(initial_lambda > 0)) return fail("initial_lambda must be positive");
  return true;
}

bool is_linear_in_parameters(const Expression& e) {
  // Per subtree: 0 = free of parameters, 1 = affine in them, 2 = nonlinear.
  std::vector<int> deg;
  deg.reserve(e.nodes.size());
  for (const Node& n : e.nodes) {
    const int a = arity(n.op);
    int d[3] = {0, 0, 0};
    for (int k = a - 1; k >= 0; --k) {
      d[k] = deg.back();
      deg.pop_back();
    }
    int r = 0;
    switch (n.op) {
      case Op::Param: r = 1; break;
      case Op::Const:
      case Op::Var: r = 0; break;
      case Op::Add:
      case Op::Sub: r = std::max(d[0], d[1]); break;
      case Op::Neg: r = d[0]; break;
      case Op::Mul: r = (d[0] == 0 || d[1] == 0) ? std::max(d[0], d[1]) : 2; break;
      case Op::Div: r = d[1] == 0 ? d[0] : 2; break;
      case Op::Fma: r = (d[0] == 0 || d[1] == 0) ? std::max({d[0], d[1], d[2]}) : 2; break;
      default: r = (d[0] | d[1] | d[2]) == 0 ? 0 : 2; break;
    }
    deg.push_back(r);
  }
  return deg.size() == 1 && deg.back() <= 1;
}

void fit_parameters(const FitOptions& options, const FitProblem& problem, FitSummary* summary) {
  std::string why;
  if (!options.is_valid(&why)) throw Error(why, {"fit options"});
  if (problem.expression == nullptr) throw Error("fit_parameters: no expression");
  const Expression& e0 = *problem.expression;
  if (problem.columns.size() != e0.variables.size())
    throw Error("fit_parameters: " + std::to_string(e0.variables.size()) + " variables but " +
                std::to_string(problem.columns.size()) + " columns");
  Expression e = e0;
  e.parameter_values.resize(e.parameters.size(), 0.0);
  FitSummary s;
  std::vector<double> values;
  s.initial_cost = options.minimax ? max_error(problem, e, values) : cost_at(problem, e, values);
  s.final_cost = s.initial_cost;
  s.parameters = e.parameter_values;
  const bool linear = options.use_linear_solver && is_linear_in_parameters(e);
  if (e.parameters.empty())
    s.termination = "no parameters";
  else if (options.minimax)
    fit_minimax(options, problem, linear, e, &s);
  else if (linear)
    fit_linear(problem, e, &s);
  else
    fit_levenberg_marquardt(options, problem, e, &s);
  *summary = std::move(s);
}

std::string FitSummary::brief_report() const {
  char buf[256];
  std::snprintf(buf, sizeof buf, "%s%s: cost %.6g -> %.6g in %d iteration%s (%s)\n",
                linear ? "linear least squares" : "Levenberg-Marquardt",
                minimax_passes > 0 ? " + Lawson minimax" : "", initial_cost, final_cost, iterations,
                iterations == 1 ? "" : "s", termination.c_str());
  return buf;
}

}  // namespace shaderfit
