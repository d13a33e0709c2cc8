// The driver of the kernel-conditions method: per form, the exact, least-squares or minimax
// solve, then the pole check, the error metrics and the cost; then the ranking.
#include "shaderfit/rational/solve.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "rational/linear_rows.hpp"
#include "rational/nonlinear.hpp"
#include "rational/remez.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/cost/cost_model.hpp"
#include "shaderfit/expr/print.hpp"

namespace shaderfit::rational {

namespace {

using Eigen::Index;
using rational_detail::ResolvedCondition;

// What every form of one problem shares: the resolved conditions and the reference on a grid.
struct Workspace {
  std::vector<ResolvedCondition> conditions;
  std::vector<double> params;  // the target's
  std::vector<double> xs, fs;  // uniform grid and the reference on it
};

Workspace make_workspace(const RationalOptions& options, const RationalProblem& problem) {
  Workspace ws;
  ws.conditions = rational_detail::resolve_conditions(problem);
  ws.params = problem.target_parameter_values();
  const int n = std::max(options.samples, 2);
  for (int i = 0; i < n; ++i) {
    const double x =
        i + 1 == n ? problem.domain.hi : problem.domain.lo + problem.domain.width() * i / (n - 1);
    ws.xs.push_back(x);
    ws.fs.push_back(problem.target.value(x, ws.params));
  }
  return ws;
}

std::string plural(int n, const char* word) {
  return fmt::format("{} {}{}", n, word, n == 1 ? "" : "s");
}

SourceLocation conditions_location(const RationalProblem& p) {
  return p.conditions.empty() ? SourceLocation{"conditions"}
                              : SourceLocation{p.conditions[0].where.source};
}

// The rows of the linear conditions; `all_linear` tells whether every condition had one.
Eigen::MatrixXd linear_rows(const RationalForm& form, const Workspace& ws, bool* all_linear,
                            std::vector<std::size_t>* nonlinear = nullptr) {
  std::vector<Eigen::RowVectorXd> rows;
  *all_linear = true;
  for (std::size_t i = 0; i < ws.conditions.size(); ++i) {
    auto r = rational_detail::linear_row(form, ws.conditions[i], ws.conditions);
    if (r) {
      rows.push_back(*r);
    } else {
      *all_linear = false;
      if (nonlinear) nonlinear->push_back(i);
    }
  }
  Eigen::MatrixXd m(static_cast<Index>(rows.size()), form.coefficient_count() + 1);
  for (std::size_t i = 0; i < rows.size(); ++i) m.row(static_cast<Index>(i)) = rows[i];
  return m;
}

// Homogeneous rows -> normalised (q0 = 1): the q0 column moves to the right-hand side.
void normalise(const RationalForm& form, const Eigen::MatrixXd& h, Eigen::MatrixXd* a,
               Eigen::VectorXd* b) {
  const Index q0 = form.numerator_degree + 1;
  *a = Eigen::MatrixXd(h.rows(), h.cols() - 1);
  a->leftCols(q0) = h.leftCols(q0);
  a->rightCols(h.cols() - 1 - q0) = h.rightCols(h.cols() - 1 - q0);
  *b = -h.col(q0);
}

// Linearised least squares to the reference, min |P - f Q| on the grid, under the linear rows:
// the starting point of every nonlinear solve.
Eigen::VectorXd linearised_start(const RationalForm& form, const Workspace& ws,
                                 const Eigen::MatrixXd& rows) {
  const int m = form.numerator_degree, n = form.denominator_degree;
  Eigen::MatrixXd a(static_cast<Index>(ws.xs.size()), m + n + 2);
  for (std::size_t s = 0; s < ws.xs.size(); ++s) {
    const double t = form.variable(ws.xs[s]);
    double tp = 1;
    for (int i = 0; i <= std::max(m, n); ++i, tp *= t) {
      if (i <= m) a(static_cast<Index>(s), i) = tp;
      if (i <= n) a(static_cast<Index>(s), m + 1 + i) = -ws.fs[s] * tp;
    }
  }
  Eigen::MatrixXd al, el;
  Eigen::VectorXd bl, dl;
  normalise(form, a, &al, &bl);
  normalise(form, rows, &el, &dl);
  return rational_detail::constrained_least_squares(al, bl, el, dl);
}

Eigen::VectorXd condition_residuals(const RationalForm& form, const Workspace& ws,
                                    const Eigen::VectorXd& c) {
  const Rational r = rational_detail::rational_from(form, c);
  Eigen::VectorXd g(static_cast<Index>(ws.conditions.size()));
  for (std::size_t i = 0; i < ws.conditions.size(); ++i)
    g(static_cast<Index>(i)) = rational_detail::condition_residual(r, ws.conditions[i]);
  return g;
}

Eigen::VectorXd sample_residuals(const RationalForm& form, const Workspace& ws,
                                 const Eigen::VectorXd& c) {
  const Rational r = rational_detail::rational_from(form, c);
  const double w = 1.0 / std::sqrt(static_cast<double>(ws.xs.size()));
  Eigen::VectorXd out(static_cast<Index>(ws.xs.size()));
  for (std::size_t i = 0; i < ws.xs.size(); ++i)
    out(static_cast<Index>(i)) = w * (r(ws.xs[i]) - ws.fs[i]);
  return out;
}

void take_nonlinear(FormResult& res, const rational_detail::NonlinearOutcome& o,
                    const RationalForm& form, const RationalOptions& options, bool square) {
  res.rational = rational_detail::rational_from(form, o.x);
  res.condition_number = o.condition_number;
  if (square && o.rank_deficient) {
    res.status = FormStatus::Singular;
    res.message = fmt::format(
        "singular system (condition number {:.3g}): the conditions do not determine form {}",
        o.condition_number, form.name("x"));
  } else if (!o.converged) {
    res.status = FormStatus::NotConverged;
    res.message =
        fmt::format("Newton did not meet the conditions (residual {:.3g} after {} iterations)",
                    o.constraint_norm, o.iterations);
  } else {
    res.status =
        o.condition_number > options.ill_conditioned ? FormStatus::IllConditioned : FormStatus::Ok;
  }
}

void solve_exact(FormResult& res, const RationalOptions& options, const Workspace& ws) {
  const RationalForm& form = res.form;
  bool all_linear = false;
  const Eigen::MatrixXd rows = linear_rows(form, ws, &all_linear);
  if (!all_linear) {
    rational_detail::NonlinearSystem sys;
    sys.constraints = [&](const Eigen::VectorXd& c) { return condition_residuals(form, ws, c); };
    take_nonlinear(res,
                   rational_detail::nonlinear_least_squares(sys, linearised_start(form, ws, rows)),
                   form, options, true);
    return;
  }
  Eigen::MatrixXd a;
  Eigen::VectorXd b;
  normalise(form, rows, &a, &b);
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(a, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const auto& s = svd.singularValues();
  const double cond =
      s(s.size() - 1) > 0 ? s(0) / s(s.size() - 1) : std::numeric_limits<double>::infinity();
  res.condition_number = cond;
  if (!(s(s.size() - 1) > 1e-14 * s(0))) {
    res.status = FormStatus::Singular;
    res.message = fmt::format(
        "singular system (condition number {:.3g}): the conditions do not determine form {}", cond,
        form.name("x"));
    return;
  }
  // LU with one step of iterative refinement: exact coefficients stay exact (F0, 0, ..., 1 - F0).
  Eigen::FullPivLU<Eigen::MatrixXd> lu(a);
  Eigen::VectorXd c = lu.solve(b);
  c += lu.solve(b - a * c);
  res.rational = rational_detail::rational_from(form, c);
  res.status = cond > options.ill_conditioned ? FormStatus::IllConditioned : FormStatus::Ok;
  if (res.status == FormStatus::IllConditioned)
    res.message = fmt::format("ill-conditioned system (condition number {:.3g})", cond);
}

void solve_least_squares(FormResult& res, const RationalOptions& options, const Workspace& ws) {
  const RationalForm& form = res.form;
  bool all_linear = false;
  const Eigen::MatrixXd rows = linear_rows(form, ws, &all_linear);
  rational_detail::NonlinearSystem sys;
  const bool over = static_cast<int>(ws.conditions.size()) > form.coefficient_count();
  Eigen::VectorXd start;
  if (over) {  // more conditions than coefficients: meet them in the least-squares sense
    sys.residuals = [&](const Eigen::VectorXd& c) { return condition_residuals(form, ws, c); };
    start = linearised_start(form, ws, Eigen::MatrixXd(0, rows.cols()));
  } else {
    sys.constraints = [&](const Eigen::VectorXd& c) { return condition_residuals(form, ws, c); };
    sys.residuals = [&](const Eigen::VectorXd& c) { return sample_residuals(form, ws, c); };
    start = linearised_start(form, ws, rows);
  }
  const rational_detail::NonlinearOutcome o = rational_detail::nonlinear_least_squares(sys, start);
  if (over) {
    res.rational = rational_detail::rational_from(form, o.x);
    res.status = FormStatus::Ok;
    res.message = fmt::format("conditions met in the least-squares sense (residual norm {:.3g})",
                              o.residual_norm);
    return;
  }
  take_nonlinear(res, o, form, options, false);
}

void solve_minimax(FormResult& res, const RationalOptions& options, const RationalProblem& problem,
                   const Workspace& ws) {
  bool all_linear = false;
  std::vector<std::size_t> nonlinear;
  const Eigen::MatrixXd rows = linear_rows(res.form, ws, &all_linear, &nonlinear);
  if (!all_linear) {
    const Condition& c = *ws.conditions[nonlinear.front()].source;
    throw Error(
        fmt::format("condition '{}' is not linear in the coefficients of form {}, so a minimax fit "
                    "cannot keep it exact (use RationalOptions::fit = Fit::LeastSquares)",
                    c.text, res.form.name(problem.target.variable())),
        c.where);
  }
  rational_detail::MinimaxOutcome o =
      rational_detail::remez(problem.target, ws.params, problem.domain, res.form, rows,
                             options.relative_minimax, options.minimax);
  res.status = o.status;
  res.message = o.message;
  res.rational = o.rational;
  res.minimax = o.equioscillation;
}

// Pole check, metrics, expression and cost.
void finish(FormResult& res, const RationalProblem& problem, const Workspace& ws) {
  if (!res.usable() && res.status != FormStatus::NotConverged) return;
  if (res.rational.p.empty()) return;
  res.rational.clean();
  const std::string& v = problem.target.variable();
  if (auto z = denominator_zero(res.rational, problem.domain)) {
    res.status = FormStatus::PoleInDomain;
    res.message =
        fmt::format("denominator {} vanishes at {} = {:.6g} in the domain [{}, {}]",
                    to_infix(Rational{res.rational.form, res.rational.q, {1.0}}.to_expression(v)),
                    v, *z, format_number(problem.domain.lo), format_number(problem.domain.hi));
    return;
  }
  double sq = 0, fmax = 0;
  for (double f : ws.fs) fmax = std::max(fmax, std::abs(f));
  res.rmse = res.max_abs = res.max_rel = 0;
  for (std::size_t i = 0; i < ws.xs.size(); ++i) {
    const double e = std::abs(res.rational(ws.xs[i]) - ws.fs[i]);
    if (!std::isfinite(e)) {
      res.rmse = res.max_abs = res.max_rel = std::numeric_limits<double>::infinity();
      break;
    }
    sq += e * e;
    res.max_abs = std::max(res.max_abs, e);
    if (std::abs(ws.fs[i]) > 1e-12 * fmax)
      res.max_rel = std::max(res.max_rel, e / std::abs(ws.fs[i]));
  }
  if (std::isfinite(res.rmse)) res.rmse = std::sqrt(sq / static_cast<double>(ws.xs.size()));
  res.expression = res.rational.to_expression(v);
  res.formula = to_infix(res.expression);
  res.cost = expression_cost(res.expression, CostTarget::Instructions);
}

FormResult solve_in(const RationalOptions& options, const RationalProblem& problem,
                    const Workspace& ws, const RationalForm& form) {
  FormResult res;
  res.form = form;
  const int count = form.coefficient_count(), conds = static_cast<int>(ws.conditions.size());
  const std::string name = form.name(problem.target.variable());
  if (options.fit == Fit::None && conds > count)
    throw Error(
        fmt::format("{} but form {} has only {}: drop {} or meet them in the least-squares sense "
                    "with RationalOptions::fit = Fit::LeastSquares",
                    plural(conds, "condition"), name, plural(count, "coefficient"), conds - count),
        conditions_location(problem));
  if (options.fit == Fit::None && conds < count)
    throw Error(
        fmt::format("form {} has {} but there {} {}: add {} or fit the rest to the reference "
                    "with RationalOptions::fit = Fit::LeastSquares or Fit::Minimax",
                    name, plural(count, "coefficient"), conds == 1 ? "is" : "are",
                    plural(conds, "condition"), count - conds),
        conditions_location(problem));
  if (options.fit == Fit::Minimax && conds > count)
    throw Error(fmt::format("{} but form {} has only {}: a minimax fit keeps every condition exact",
                            plural(conds, "condition"), name, plural(count, "coefficient")),
                conditions_location(problem));
  if (options.fit == Fit::None || (options.fit == Fit::Minimax && conds == count))
    solve_exact(res, options, ws);
  else if (options.fit == Fit::LeastSquares)
    solve_least_squares(res, options, ws);
  else
    solve_minimax(res, options, problem, ws);
  finish(res, problem, ws);
  return res;
}

}  // namespace

FormResult solve_form(const RationalOptions& options, const RationalProblem& problem,
                      const RationalForm& form) {
  problem.validate();
  const Workspace ws = make_workspace(options, problem);
  return solve_in(options, problem, ws, form);
}

void solve(const RationalOptions& options, const RationalProblem& problem,
           RationalSummary* summary) {
  std::string why;
  if (!options.is_valid(&why)) throw Error("invalid options: " + why);
  problem.validate();
  const Workspace ws = make_workspace(options, problem);
  std::vector<RationalForm> forms = problem.forms;
  if (forms.empty()) {
    std::vector<Transform> transforms = options.transforms;
    if (transforms.empty())
      transforms = {Transform::identity(), Transform::reflection(problem.domain)};
    const int count = options.coefficient_count > 0 ? options.coefficient_count
                                                    : static_cast<int>(problem.conditions.size());
    if (count < 1)
      throw Error("no conditions and no coefficient count: nothing to solve",
                  conditions_location(problem));
    forms = enumerate_forms(count, transforms);
  }
  summary->variable = problem.target.variable();
  summary->rank_by = options.rank_by;
  summary->results.clear();
  ProgressCounter progress(options.on_progress, forms.size(), "forms");
  for (const RationalForm& f : forms) {
    summary->results.push_back(solve_in(options, problem, ws, f));
    progress.add();
  }
  const Loss by = options.rank_by;
  std::stable_sort(summary->results.begin(), summary->results.end(),
                   [by](const FormResult& a, const FormResult& b) {
                     if (a.usable() != b.usable()) return a.usable();
                     if (!a.usable()) return false;
                     if (a.error(by) != b.error(by)) return a.error(by) < b.error(by);
                     return a.cost < b.cost;
                   });
  // Pareto front: sweep by cost, keep those strictly better than every cheaper one.
  std::vector<std::size_t> usable;
  for (std::size_t i = 0; i < summary->results.size(); ++i)
    if (summary->results[i].usable()) usable.push_back(i);
  std::stable_sort(usable.begin(), usable.end(), [&](std::size_t a, std::size_t b) {
    const FormResult &x = summary->results[a], &y = summary->results[b];
    return x.cost != y.cost ? x.cost < y.cost : x.error(by) < y.error(by);
  });
  summary->pareto.clear();
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i : usable) {
    const double e = summary->results[i].error(by);
    if (e < best * (1 - 1e-9)) {
      summary->pareto.push_back(i);
      best = e;
    }
  }
}

}  // namespace shaderfit::rational
