// The joint solve of global and per-block parameters: one parameter vector holding the globals,
// then each block's own, with dense normal equations assembled block by block (blocks in
// parallel). Constraints are expanded per block (a relation between global parameters once).
#include <algorithm>
#include <cmath>
#include <limits>

#include "fixed_form_internal.hpp"
#include "shaderfit/core/parallel.hpp"

namespace shaderfit::fit_detail {

namespace {

using Index = Eigen::Index;

struct Layout {
  std::vector<std::size_t> active;     // blocks with rows
  std::vector<std::ptrdiff_t> global;  // per formula parameter: slot among the globals, or -1
  std::vector<std::ptrdiff_t> local;   // per formula parameter: slot among a block's own, or -1
  std::size_t n_global = 0, n_local = 0, size = 0;
  std::vector<std::string> names;
  std::vector<bool> global_only;  // per constraint: a relation between global parameters only

  std::size_t index(std::size_t a, std::size_t j) const {
    return global[j] >= 0 ? static_cast<std::size_t>(global[j])
                          : n_global + a * n_local + static_cast<std::size_t>(local[j]);
  }
};

struct Coupled {
  const Model& m;
  std::span<const PreparedBlock> blocks;
  const FixedFormOptions& o;
  Layout lay;
  std::vector<std::vector<double>> w;  // effective weights per active block
  std::vector<Linearization> lin;      // per active block, from the last assemble()
  int iterations = 0;
  std::string termination;

  const PreparedBlock& block(std::size_t a) const { return blocks[lay.active[a]]; }

  std::vector<double> params(const Eigen::VectorXd& x, std::size_t a) const {
    std::vector<double> p(m.parameters());
    for (std::size_t j = 0; j < p.size(); ++j) p[j] = x(static_cast<Index>(lay.index(a, j)));
    return p;
  }

  double cost(const Eigen::VectorXd& x) const {
    double se = 0, sw = 0;
    std::vector<double> v;
    for (std::size_t a = 0; a < lay.active.size(); ++a) {
      values(m, block(a), params(x, a), &v);
      const PreparedBlock& b = block(a);
      for (std::size_t i = 0; i < v.size(); ++i) {
        const double r = v[i] - b.target[i];
        if (w[a][i] == 0) continue;
        if (!std::isfinite(r)) return std::numeric_limits<double>::infinity();
        se += w[a][i] * r * r;
        sw += w[a][i];
      }
    }
    return sw > 0 ? se / sw : 0.0;
  }

  // H = J^T W J and g = J^T W r over all blocks, scattered into the expanded layout.
  void assemble(const Eigen::VectorXd& x, Eigen::MatrixXd* H, Eigen::VectorXd* g) {
    const std::size_t n = m.parameters(), nb = lay.active.size();
    lin.resize(nb);
    std::vector<Eigen::MatrixXd> Hb(nb);
    std::vector<Eigen::VectorXd> gb(nb);
    parallel_for(
        nb, 1,
        [&](std::size_t begin, std::size_t end) {
          for (std::size_t a = begin; a < end; ++a) {
            const PreparedBlock& b = block(a);
            linearize(m, b, params(x, a), &lin[a]);
            const Eigen::Map<const Eigen::MatrixXd> J(
                lin[a].jacobian.data(), static_cast<Index>(b.rows()), static_cast<Index>(n));
            Eigen::VectorXd sw(static_cast<Index>(b.rows())), r(static_cast<Index>(b.rows()));
            for (std::size_t i = 0; i < b.rows(); ++i) {
              sw(static_cast<Index>(i)) = std::sqrt(w[a][i]);
              r(static_cast<Index>(i)) =
                  sw(static_cast<Index>(i)) * (lin[a].values[i] - b.target[i]);
            }
            const Eigen::MatrixXd Jw = sw.asDiagonal() * J;
            Hb[a] = Jw.transpose() * Jw;
            gb[a] = Jw.transpose() * r;
          }
        },
        o.threads);
    *H = Eigen::MatrixXd::Zero(static_cast<Index>(lay.size), static_cast<Index>(lay.size));
    *g = Eigen::VectorXd::Zero(static_cast<Index>(lay.size));
    for (std::size_t a = 0; a < nb; ++a)
      for (std::size_t j = 0; j < n; ++j) {
        const auto J = static_cast<Index>(lay.index(a, j));
        (*g)(J) += gb[a](static_cast<Index>(j));
        for (std::size_t k = 0; k < n; ++k)
          (*H)(J, static_cast<Index>(lay.index(a, k))) +=
              Hb[a](static_cast<Index>(j), static_cast<Index>(k));
      }
  }

  // Expanded constraints linearised at x: C x' = d.
  void constraints(const Eigen::VectorXd& x, Eigen::MatrixXd* C, Eigen::VectorXd* d,
                   std::vector<std::string>* names) const {
    std::vector<Eigen::RowVectorXd> rows;
    std::vector<double> rhs;
    names->clear();
    std::vector<double> grad(m.parameters());
    for (std::size_t a = 0; a < lay.active.size(); ++a) {
      const std::vector<double> p = params(x, a);
      for (const ConstraintInstance& ci : block(a).constraints) {
        if (a > 0 && lay.global_only[ci.index]) continue;
        double v = 0;
        constraint_row(m, ci, p, &v, grad);
        Eigen::RowVectorXd row = Eigen::RowVectorXd::Zero(static_cast<Index>(lay.size));
        for (std::size_t j = 0; j < grad.size(); ++j)
          row(static_cast<Index>(lay.index(a, j))) += grad[j];
        rhs.push_back(row.dot(x) - v);
        rows.push_back(std::move(row));
        names->push_back(lay.global_only[ci.index]
                             ? ci.constraint->text
                             : ci.constraint->text + " [" + block(a).block->label + "]");
      }
    }
    C->resize(static_cast<Index>(rows.size()), static_cast<Index>(lay.size));
    d->resize(static_cast<Index>(rows.size()));
    for (std::size_t r = 0; r < rows.size(); ++r) {
      C->row(static_cast<Index>(r)) = rows[r];
      (*d)(static_cast<Index>(r)) = rhs[r];
    }
  }

  Failure eliminate_at(const Eigen::VectorXd& x, bool tangent, Elimination* e) const {
    Eigen::MatrixXd C;
    Eigen::VectorXd d;
    std::vector<std::string> rows;
    constraints(x, &C, &d, &rows);
    if (!C.allFinite() || !d.allFinite())
      return {FailureKind::nonfinite, "a constraint is not finite"};
    if (tangent) d.setZero();
    return eliminate(C, d, rows, o.constraint_tolerance, e);
  }

  std::vector<std::string> free_names(const Elimination& e) const {
    std::vector<std::string> out;
    for (int j : e.free) out.push_back(lay.names[static_cast<std::size_t>(j)]);
    return out;
  }

  // Gauss-Newton onto the constraints, minimum-norm steps.
  Failure project(Eigen::VectorXd* x) const {
    Eigen::MatrixXd C;
    Eigen::VectorXd d;
    std::vector<std::string> rows;
    for (int it = 0; it < 50; ++it) {
      constraints(*x, &C, &d, &rows);
      const Eigen::VectorXd c = C * *x - d;
      if (!c.allFinite()) break;
      if (c.rows() == 0 || c.cwiseAbs().maxCoeff() <= o.constraint_tolerance) return {};
      *x -= C.completeOrthogonalDecomposition().solve(c);
    }
    return {FailureKind::contradiction, "the constraints cannot all be met"};
  }

  bool constrained() const {
    for (std::size_t a = 0; a < lay.active.size(); ++a)
      if (!block(a).constraints.empty()) return true;
    return false;
  }

  Failure linear(Eigen::VectorXd* x) {
    Eigen::MatrixXd H;
    Eigen::VectorXd g;
    assemble(*x, &H, &g);
    Elimination e;
    if (Failure f = eliminate_at(*x, false, &e)) return f;
    const Eigen::MatrixXd Hr = e.Z.transpose() * H * e.Z;
    const Eigen::VectorXd rhs = -e.Z.transpose() * (H * (e.p0 - *x) + g);
    Eigen::VectorXd q;
    if (Failure f = solve_normal(Hr, rhs, free_names(e), o.rank_tolerance, &q)) return f;
    const Eigen::VectorXd next = e.p0 + e.Z * q;
    ++iterations;
    termination = "linear";
    if (!m.structurally_linear) {
      std::vector<double> v;
      for (std::size_t a = 0; a < lay.active.size(); ++a) {
        const std::vector<double> p0 = params(*x, a), p1 = params(next, a);
        values(m, block(a), p1, &v);
        const std::size_t rows = block(a).rows(), n = p0.size();
        for (std::size_t i = 0; i < rows; ++i) {
          double want = lin[a].values[i];
          for (std::size_t j = 0; j < n; ++j)
            want += lin[a].jacobian[j * rows + i] * (p1[j] - p0[j]);
          if (!(std::abs(v[i] - want) <= 1e-7 * (1 + std::abs(want))))
            return {FailureKind::not_linear, "not linear in the parameters"};
        }
      }
    }
    *x = next;
    return {};
  }

  // The joint residuals for the solver: normal equations on the constraints' tangent space,
  // steps mapped back and projected onto the constraints.
  struct Residuals final : LeastSquaresProblem {
    explicit Residuals(Coupled& joint) : c(joint), con(joint.constrained()) {}

    void linearize(std::span<const double> xs, LeastSquaresLinearization* out) override {
      const Eigen::Map<const Eigen::VectorXd> x(xs.data(), static_cast<Index>(xs.size()));
      Eigen::MatrixXd H;
      Eigen::VectorXd g;
      c.assemble(x, &H, &g);
      if (con) {
        if (Failure f = c.eliminate_at(x, true, &e)) {
          failure = std::move(f);  // ends the iterations (non-finite normal equations)
          out->n = 1;
          out->h.assign(1, std::numeric_limits<double>::quiet_NaN());
          out->g.assign(1, 0.0);
          return;
        }
      } else {
        e.Z = Eigen::MatrixXd::Identity(x.size(), x.size());
      }
      const Eigen::MatrixXd Hr = e.Z.transpose() * H * e.Z;
      const Eigen::VectorXd gr = e.Z.transpose() * g;
      out->n = static_cast<std::size_t>(Hr.rows());
      out->h.assign(Hr.data(), Hr.data() + Hr.size());
      out->g.assign(gr.data(), gr.data() + gr.size());
    }

    double cost(std::span<const double> xs) override {
      return c.cost(Eigen::Map<const Eigen::VectorXd>(xs.data(), static_cast<Index>(xs.size())));
    }

    bool step(std::span<const double> xs, std::span<const double> dz, std::vector<double>* trial,
              std::vector<double>* moved) override {
      const Eigen::Map<const Eigen::VectorXd> x(xs.data(), static_cast<Index>(xs.size()));
      Eigen::VectorXd t =
          x + e.Z * Eigen::Map<const Eigen::VectorXd>(dz.data(), static_cast<Index>(dz.size()));
      if (con && c.project(&t)) return false;
      trial->assign(t.data(), t.data() + t.size());
      moved->resize(xs.size());
      for (std::size_t j = 0; j < xs.size(); ++j) (*moved)[j] = (*trial)[j] - xs[j];
      return true;
    }

    Coupled& c;
    bool con;
    Elimination e;
    Failure failure;
  };

  Failure levenberg_marquardt(Eigen::VectorXd* x) {
    const bool con = constrained();
    Elimination e;
    if (con) {
      if (Failure f = eliminate_at(*x, false, &e)) return f;
      if (Failure f = project(x)) return f;
    }
    if (!std::isfinite(cost(*x)))
      return {FailureKind::nonfinite,
              "the fitted values are not finite at the starting parameters"};
    Residuals residuals(*this);
    std::vector<double> xs(x->data(), x->data() + x->size());
    LeastSquaresSummary ls;
    shaderfit::levenberg_marquardt(lm_options(o), residuals, &xs, &ls);
    *x = Eigen::Map<const Eigen::VectorXd>(xs.data(), x->size());
    iterations += ls.iterations;
    termination = termination_name(ls.termination);
    if (residuals.failure) return residuals.failure;
    Eigen::MatrixXd H;
    Eigen::VectorXd g;
    const auto size = static_cast<Index>(lay.size);
    assemble(*x, &H, &g);
    if (con) {
      if (Failure f = eliminate_at(*x, true, &e)) return f;
    } else {
      e.Z = Eigen::MatrixXd::Identity(size, size);
      e.free.clear();
      for (Index j = 0; j < size; ++j) e.free.push_back(static_cast<int>(j));
    }
    Eigen::VectorXd q;
    return solve_normal(e.Z.transpose() * H * e.Z, Eigen::VectorXd::Zero(e.Z.cols()), free_names(e),
                        o.rank_tolerance, &q);
  }

  // By the solver SolverChoice picks.
  Failure least_squares(Eigen::VectorXd* x) {
    return SolverChoice::of(m, o).least_squares([&] { return linear(x); },
                                                [&] { return levenberg_marquardt(x); });
  }

  // Lawson's reweighting over the rows of all blocks, in one flat order.
  Failure minimax(Eigen::VectorXd* x) {
    std::vector<double> flat;
    for (std::size_t a = 0; a < lay.active.size(); ++a)
      flat.insert(flat.end(), block(a).weights.begin(), block(a).weights.end());
    Eigen::VectorXd best = *x;
    LawsonSteps steps;
    steps.solve = [&](std::span<const double> eff) {
      std::size_t at = 0;
      for (std::size_t a = 0; a < lay.active.size(); ++a)
        for (double& wi : w[a]) wi = eff[at++];
      return least_squares(x);
    };
    steps.residuals = [&](std::vector<double>* r) {
      std::vector<double> v;
      std::size_t at = 0;
      for (std::size_t a = 0; a < lay.active.size(); ++a) {
        values(m, block(a), params(*x, a), &v);
        for (std::size_t i = 0; i < v.size(); ++i) (*r)[at++] = std::abs(v[i] - block(a).target[i]);
      }
    };
    steps.keep = [&] { best = *x; };
    steps.restore = [&] { *x = best; };
    return lawson(flat, o.minimax_iterations, steps, &termination);
  }
};

}  // namespace

std::vector<BlockResult> solve_coupled(const Model& m, std::span<const PreparedBlock> blocks,
                                       const FixedFormOptions& o,
                                       std::span<const std::vector<double>> starts,
                                       Failure* failure) {
  Coupled c{m, blocks, o, {}, {}, {}};
  Layout& lay = c.lay;
  const std::size_t n = m.parameters();
  lay.global.assign(n, -1);
  lay.local.assign(n, -1);
  for (std::size_t j = 0; j < n; ++j) {
    if (m.scopes[j] == ParameterScope::global)
      lay.global[j] = static_cast<std::ptrdiff_t>(lay.n_global++);
    else
      lay.local[j] = static_cast<std::ptrdiff_t>(lay.n_local++);
  }
  for (std::size_t b = 0; b < blocks.size(); ++b)
    if (blocks[b].rows() > 0) lay.active.push_back(b);
  lay.size = lay.n_global + lay.active.size() * lay.n_local;
  lay.names.resize(lay.size);
  for (std::size_t a = 0; a < std::max<std::size_t>(lay.active.size(), 1); ++a)
    for (std::size_t j = 0; j < n; ++j) {
      if (a >= lay.active.size() && lay.local[j] >= 0) continue;
      lay.names[lay.index(a, j)] =
          m.formula.parameters[j] +
          (lay.local[j] >= 0 ? " [" + blocks[lay.active[a]].block->label + "]" : "");
    }
  for (const Constraint& k : m.constraints) {
    bool only = k.kind == Constraint::Kind::parameters;
    for (const Node& node : k.lhs.nodes)
      if (node.op == Op::Param &&
          m.scopes[static_cast<std::size_t>(node.index)] != ParameterScope::global)
        only = false;
    lay.global_only.push_back(only);
  }
  std::vector<BlockResult> results(blocks.size());
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    results[b].label = blocks[b].block->label;
    results[b].rows = blocks[b].rows();
    results[b].parameters = starts[b];
  }
  if (lay.size > o.max_coupled_parameters) {
    *failure = {FailureKind::too_large, "the joint fit of global and per-block parameters has " +
                                            std::to_string(lay.size) +
                                            " parameters, more than max_coupled_parameters (" +
                                            std::to_string(o.max_coupled_parameters) + ")"};
    return results;
  }
  Eigen::VectorXd x = Eigen::VectorXd::Zero(static_cast<Index>(lay.size));
  for (std::size_t a = 0; a < lay.active.size(); ++a)
    for (std::size_t j = 0; j < n; ++j)
      x(static_cast<Index>(lay.index(a, j))) = starts[lay.active[a]][j];
  for (std::size_t a = 0; a < lay.active.size(); ++a) c.w.push_back(c.block(a).weights);
  std::vector<double> initial(blocks.size());
  std::vector<double> v;
  const SolverChoice choice = SolverChoice::of(m, o);
  const Loss loss = choice.loss();
  for (std::size_t a = 0; a < lay.active.size(); ++a) {
    values(m, c.block(a), c.params(x, a), &v);
    results[lay.active[a]].initial_cost = fit_cost(loss, v, c.block(a).target, c.block(a).weights);
  }
  *failure = choice.minimax ? c.minimax(&x) : c.least_squares(&x);
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    if (blocks[b].rows() == 0) {
      results[b].ok = false;
      results[b].failure = "no data rows";
    }
  }
  for (std::size_t a = 0; a < lay.active.size(); ++a) {
    BlockResult& r = results[lay.active[a]];
    r.iterations = c.iterations;
    if (*failure) {
      r.ok = false;
      r.failure = failure->message;
      r.termination = "failed";
      r.final_cost = r.initial_cost;
      continue;
    }
    r.parameters = c.params(x, a);
    r.termination = c.termination;
    residual_stats(m, c.block(a), r.parameters, &r);
  }
  return results;
}

}  // namespace shaderfit::fit_detail
