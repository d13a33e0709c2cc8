// Solving one block on its own: constrained linear least squares (design matrix, QR), constrained
// Levenberg-Marquardt (normal equations on the constraints' tangent space, with projection back
// onto nonlinear constraints), and Lawson's reweighting for the minimax loss around either.
#include <algorithm>
#include <cmath>
#include <limits>

#include "fixed_form_internal.hpp"

namespace shaderfit::fit_detail {

namespace {

using Index = Eigen::Index;

struct Context {
  const Model& m;
  const PreparedBlock& b;
  const FixedFormOptions& o;
  std::vector<std::string> names;  // one per parameter
  int iterations = 0;
  std::string termination;
};

double weighted_cost(const Context& c, std::span<const double> w, std::span<const double> p) {
  std::vector<double> v;
  values(c.m, c.b, p, &v);
  return fit_cost(Loss::Mse, v, c.b.target, w);
}

// The constraints linearised at p: C p' = d is c(p) + C (p' - p) = 0.
void constraint_system(const Context& c, std::span<const double> p, Eigen::MatrixXd* C,
                       Eigen::VectorXd* d, std::vector<std::string>* row_names) {
  const auto k = static_cast<Index>(c.b.constraints.size());
  const auto n = static_cast<Index>(p.size());
  C->resize(k, n);
  d->resize(k);
  row_names->clear();
  std::vector<double> grad(p.size());
  const Eigen::Map<const Eigen::VectorXd> pv(p.data(), n);
  for (Index r = 0; r < k; ++r) {
    double v = 0;
    constraint_row(c.m, c.b.constraints[static_cast<std::size_t>(r)], p, &v, grad);
    for (Index j = 0; j < n; ++j) (*C)(r, j) = grad[static_cast<std::size_t>(j)];
    (*d)(r) = C->row(r).dot(pv) - v;
    row_names->push_back(c.b.constraints[static_cast<std::size_t>(r)].constraint->text);
  }
}

Failure eliminate_at(const Context& c, std::span<const double> p, bool tangent, Elimination* e) {
  Eigen::MatrixXd C;
  Eigen::VectorXd d;
  std::vector<std::string> rows;
  constraint_system(c, p, &C, &d, &rows);
  if (!C.allFinite() || !d.allFinite())
    return {FailureKind::nonfinite, "a constraint is not finite at the parameters"};
  if (tangent) d.setZero();
  return eliminate(C, d, rows, c.o.constraint_tolerance, e);
}

std::vector<std::string> free_names(const Context& c, const Elimination& e) {
  std::vector<std::string> out;
  for (int j : e.free) out.push_back(c.names[static_cast<std::size_t>(j)]);
  return out;
}

// One constrained linear least-squares solve around p (exact when the model is linear).
Failure linear_solve(Context& c, std::span<const double> w, std::vector<double>* p) {
  const std::size_t rows = c.b.rows(), n = p->size();
  Linearization L;
  linearize(c.m, c.b, *p, &L);
  Elimination e;
  if (Failure f = eliminate_at(c, *p, false, &e)) return f;
  const Eigen::Map<const Eigen::MatrixXd> J(L.jacobian.data(), static_cast<Index>(rows),
                                            static_cast<Index>(n));
  const Eigen::Map<const Eigen::VectorXd> pl(p->data(), static_cast<Index>(n));
  Eigen::VectorXd sw(static_cast<Index>(rows)), rhs(static_cast<Index>(rows));
  const Eigen::VectorXd shift = J * (pl - e.p0);
  for (std::size_t i = 0; i < rows; ++i) {
    sw(static_cast<Index>(i)) = std::sqrt(w[i]);
    rhs(static_cast<Index>(i)) =
        sw(static_cast<Index>(i)) * (c.b.target[i] - L.values[i] + shift(static_cast<Index>(i)));
  }
  const Eigen::MatrixXd A = sw.asDiagonal() * (J * e.Z);
  Eigen::VectorXd q;
  if (Failure f = solve_design(A, rhs, free_names(c, e), c.o.rank_tolerance, &q)) return f;
  const Eigen::VectorXd solution = e.p0 + e.Z * q;
  std::vector<double> next(solution.data(), solution.data() + n);
  ++c.iterations;
  c.termination = "linear";
  if (!c.m.structurally_linear) {
    // Sampled linearity: the prediction must hold at the solution, or this block is nonlinear.
    std::vector<double> v;
    values(c.m, c.b, next, &v);
    const Eigen::VectorXd predicted = J * (solution - pl);
    for (std::size_t i = 0; i < rows; ++i) {
      const double want = L.values[i] + predicted(static_cast<Index>(i));
      if (!(std::abs(v[i] - want) <= 1e-7 * (1 + std::abs(want))))
        return {FailureKind::not_linear, "not linear in the parameters on this block"};
    }
  }
  *p = std::move(next);
  return {};
}

// The block's weighted residuals for the solver: normal equations on the constraints' tangent
// space (all parameters without constraints), steps mapped back and projected onto nonlinear
// constraints.
class BlockResiduals final : public LeastSquaresProblem {
 public:
  BlockResiduals(const Context& c, std::span<const double> w) : c_(c), w_(w) {
    const std::size_t rows = c.b.rows();
    sw_.resize(static_cast<Index>(rows));
    for (std::size_t i = 0; i < rows; ++i) sw_(static_cast<Index>(i)) = std::sqrt(w[i]);
  }

  void linearize(std::span<const double> p, LeastSquaresLinearization* out) override {
    const std::size_t rows = c_.b.rows(), n = p.size();
    Linearization L;
    shaderfit::fit_detail::linearize(c_.m, c_.b, p, &L);
    if (constrained()) {
      if (Failure f = eliminate_at(c_, p, true, &e_)) {
        failure_ = std::move(f);  // ends the iterations (non-finite normal equations)
        out->n = 1;
        out->h.assign(1, std::numeric_limits<double>::quiet_NaN());
        out->g.assign(1, 0.0);
        return;
      }
    } else if (e_.Z.rows() == 0) {
      e_.Z = Eigen::MatrixXd::Identity(static_cast<Index>(n), static_cast<Index>(n));
    }
    const Eigen::Map<const Eigen::MatrixXd> J(L.jacobian.data(), static_cast<Index>(rows),
                                              static_cast<Index>(n));
    Eigen::VectorXd r(static_cast<Index>(rows));
    for (std::size_t i = 0; i < rows; ++i)
      r(static_cast<Index>(i)) = sw_(static_cast<Index>(i)) * (L.values[i] - c_.b.target[i]);
    const Eigen::MatrixXd Jz = sw_.asDiagonal() * (J * e_.Z);
    const Eigen::MatrixXd H = Jz.transpose() * Jz;
    const Eigen::VectorXd g = Jz.transpose() * r;
    out->n = static_cast<std::size_t>(H.rows());
    out->h.assign(H.data(), H.data() + H.size());
    out->g.assign(g.data(), g.data() + g.size());
  }

  double cost(std::span<const double> p) override { return weighted_cost(c_, w_, p); }

  bool step(std::span<const double> p, std::span<const double> dz, std::vector<double>* trial,
            std::vector<double>* moved) override {
    const Eigen::VectorXd dp =
        e_.Z * Eigen::Map<const Eigen::VectorXd>(dz.data(), static_cast<Index>(dz.size()));
    trial->assign(p.begin(), p.end());
    for (std::size_t j = 0; j < p.size(); ++j) (*trial)[j] += dp(static_cast<Index>(j));
    if (constrained() && project(c_.m, c_.b, c_.o, trial)) return false;
    moved->resize(p.size());
    for (std::size_t j = 0; j < p.size(); ++j) (*moved)[j] = (*trial)[j] - p[j];
    return true;
  }

  [[nodiscard]] const Failure& failure() const { return failure_; }

 private:
  bool constrained() const { return !c_.b.constraints.empty(); }

  const Context& c_;
  std::span<const double> w_;
  Eigen::VectorXd sw_;
  Elimination e_;
  Failure failure_;
};

Failure levenberg_marquardt(Context& c, std::span<const double> w, std::vector<double>* p) {
  const std::size_t rows = c.b.rows(), n = p->size();
  const bool constrained = !c.b.constraints.empty();
  if (constrained) {
    Elimination e;
    if (Failure f = eliminate_at(c, *p, false, &e)) return f;
    if (Failure f = project(c.m, c.b, c.o, p)) return f;
  }
  if (!std::isfinite(weighted_cost(c, w, *p)))
    return {FailureKind::nonfinite, "the fitted values are not finite at the starting parameters"};
  BlockResiduals residuals(c, w);
  LeastSquaresSummary ls;
  shaderfit::levenberg_marquardt(lm_options(c.o), residuals, p, &ls);
  c.iterations += ls.iterations;
  c.termination = termination_name(ls.termination);
  if (residuals.failure()) return residuals.failure();
  Linearization L;
  Eigen::VectorXd sw(static_cast<Index>(rows));
  for (std::size_t i = 0; i < rows; ++i) sw(static_cast<Index>(i)) = std::sqrt(w[i]);
  Elimination e;
  // A parameter the data do not determine at the solution makes the system singular.
  linearize(c.m, c.b, *p, &L);
  if (constrained) {
    if (Failure f = eliminate_at(c, *p, true, &e)) return f;
  } else {
    e.Z = Eigen::MatrixXd::Identity(static_cast<Index>(n), static_cast<Index>(n));
    e.free.clear();
    for (std::size_t j = 0; j < n; ++j) e.free.push_back(static_cast<int>(j));
  }
  const Eigen::Map<const Eigen::MatrixXd> J(L.jacobian.data(), static_cast<Index>(rows),
                                            static_cast<Index>(n));
  Eigen::VectorXd q;
  return solve_design(sw.asDiagonal() * (J * e.Z), Eigen::VectorXd::Zero(static_cast<Index>(rows)),
                      free_names(c, e), c.o.rank_tolerance, &q);
}

// A least-squares solve with per-row weights w, by the solver SolverChoice picks.
Failure least_squares(Context& c, std::span<const double> w, std::vector<double>* p) {
  return SolverChoice::of(c.m, c.o).least_squares([&] { return linear_solve(c, w, p); },
                                                  [&] { return levenberg_marquardt(c, w, p); });
}

Failure minimax(Context& c, std::vector<double>* p) {
  std::vector<double> best = *p, v;
  LawsonSteps steps;
  steps.solve = [&](std::span<const double> eff) { return least_squares(c, eff, p); };
  steps.residuals = [&](std::vector<double>* r) {
    values(c.m, c.b, *p, &v);
    for (std::size_t i = 0; i < v.size(); ++i) (*r)[i] = std::abs(v[i] - c.b.target[i]);
  };
  steps.keep = [&] { best = *p; };
  steps.restore = [&] { *p = best; };
  return lawson(c.b.weights, c.o.minimax_iterations, steps, &c.termination);
}

}  // namespace

BlockResult solve_block(const Model& m, const PreparedBlock& b, const FixedFormOptions& o,
                        std::span<const double> start, FailureKind* kind) {
  BlockResult r;
  r.label = b.block->label;
  r.rows = b.rows();
  std::vector<double> p(start.begin(), start.end());
  r.parameters = p;
  if (kind != nullptr) *kind = FailureKind::none;
  if (b.rows() == 0) {
    if (kind != nullptr) *kind = FailureKind::no_rows;
    r.ok = false;
    r.failure = "no data rows";
    r.termination = "failed";
    return r;
  }
  Context c{m, b, o, m.formula.parameters};
  {
    std::vector<double> v;
    values(m, b, p, &v);
    r.initial_cost = fit_cost(SolverChoice::of(m, o).loss(), v, b.target, b.weights);
  }
  const Failure f =
      SolverChoice::of(m, o).minimax ? minimax(c, &p) : least_squares(c, b.weights, &p);
  r.iterations = c.iterations;
  if (f) {
    if (kind != nullptr) *kind = f.kind;
    r.ok = false;
    r.failure = f.message;
    r.termination = "failed";
    r.final_cost = r.initial_cost;
    return r;
  }
  r.parameters = p;
  r.termination = c.termination;
  residual_stats(m, b, p, &r);
  return r;
}

}  // namespace shaderfit::fit_detail
