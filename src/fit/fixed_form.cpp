// solve_fixed_form: validate the problem, build the fitted quantity (formula, transform of it, or
// its log), resolve constraints per block, and hand the blocks to the per-block or joint solver.
#include "shaderfit/fit/fixed_form.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "fixed_form_internal.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/core/parallel.hpp"
#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/expr/print.hpp"
#include "shaderfit/fit/fit.hpp"

namespace shaderfit {

using fit_detail::FailureKind;
using fit_detail::Model;
using fit_detail::PreparedBlock;

namespace {

constexpr std::pair<SolverKind, std::string_view> kSolverNames[] = {
    {SolverKind::automatic, "auto"},
    {SolverKind::linear, "linear"},
    {SolverKind::levenberg_marquardt, "lm"}};

// The losses FixedFormOptions::loss may name.
bool fit_minimises(Loss loss) {
  return loss == Loss::Mse || loss == Loss::Log || loss == Loss::MaxAbs;
}

}  // namespace

std::string_view solver_kind_name(SolverKind kind) {
  for (const auto& [k, name] : kSolverNames)
    if (k == kind) return name;
  return "?";
}

std::optional<SolverKind> solver_kind_from_name(std::string_view name) {
  for (const auto& [k, n] : kSolverNames)
    if (n == name) return k;
  return std::nullopt;
}

bool FixedFormOptions::is_valid(std::string* why) const {
  auto fail = [&](const char* m) {
    if (why != nullptr) *why = m;
    return false;
  };
  if (!fit_minimises(loss)) return fail("loss must be mse, log or max_abs");
  if (max_iterations < 1) return fail("max_iterations must be at least 1");
  if (minimax_iterations < 1) return fail("minimax_iterations must be at least 1");
  if (!(function_tolerance > 0) || !(parameter_tolerance > 0) || !(constraint_tolerance > 0))
    return fail("tolerances must be positive");
  if (!(rank_tolerance > 0) || !(rank_tolerance < 1))
    return fail("rank_tolerance must be in (0, 1)");
  if (!(initial_lambda > 0)) return fail("initial_lambda must be positive");
  if (threads < 0) return fail("threads must not be negative");
  if (max_coupled_parameters < 1) return fail("max_coupled_parameters must be at least 1");
  return true;
}

Expression substitute_variable(const Expression& outer, const std::string& name,
                               const Expression& inner) {
  for (const Node& n : outer.nodes)
    if (n.op == Op::Param) throw Error("substitute_variable: the outer expression has parameters");
  Expression r;
  r.variables = inner.variables;
  r.parameters = inner.parameters;
  r.parameter_values = inner.parameter_values;
  std::vector<int> map(outer.variables.size(), -1);
  for (std::size_t i = 0; i < outer.variables.size(); ++i) {
    if (outer.variables[i] == name) continue;
    auto it = std::find(r.variables.begin(), r.variables.end(), outer.variables[i]);
    if (it == r.variables.end()) it = r.variables.insert(r.variables.end(), outer.variables[i]);
    map[i] = static_cast<int>(it - r.variables.begin());
  }
  for (const Node& n : outer.nodes) {
    if (n.op == Op::Var && outer.variables[static_cast<std::size_t>(n.index)] == name) {
      r.nodes.insert(r.nodes.end(), inner.nodes.begin(), inner.nodes.end());
    } else if (n.op == Op::Var) {
      r.nodes.push_back(Node::variable(map[static_cast<std::size_t>(n.index)]));
    } else {
      r.nodes.push_back(n);
    }
  }
  r.update_lengths();
  return r;
}

namespace {

// Sampled linearity: values and Jacobian at two parameter points agree with one affine map.
bool sampled_linear(const Model& m, const PreparedBlock& b, std::vector<double> p) {
  const std::size_t rows = std::min<std::size_t>(b.rows(), 256), n = p.size();
  PreparedBlock head = b;
  head.target.resize(rows);
  fit_detail::Linearization a, c;
  fit_detail::linearize(m, head, p, &a);
  std::vector<double> q = p;
  for (std::size_t j = 0; j < n; ++j) q[j] += 0.375 + 0.125 * static_cast<double>(j % 5);
  fit_detail::linearize(m, head, q, &c);
  for (std::size_t i = 0; i < rows; ++i) {
    double want = a.values[i];
    for (std::size_t j = 0; j < n; ++j) {
      const double ja = a.jacobian[j * rows + i], jc = c.jacobian[j * rows + i];
      if (!std::isfinite(ja) || !(std::abs(ja - jc) <= 1e-8 * (1 + std::abs(ja)))) return false;
      want += ja * (q[j] - p[j]);
    }
    if (!(std::abs(c.values[i] - want) <= 1e-8 * (1 + std::abs(want)))) return false;
  }
  return rows > 0;
}

Model build_model(const FixedFormOptions& o, const FixedFormProblem& pr) {
  Model m;
  m.formula = pr.formula;
  m.formula.parameter_values.resize(m.formula.parameters.size(), 0.0);
  if (m.formula.parameters.empty())
    throw Error("the formula '" + to_infix(pr.formula) + "' has no free parameters to fit",
                {"formula"});
  m.scopes = pr.scopes.empty() ? std::vector<ParameterScope>(m.parameters(), ParameterScope::global)
                               : pr.scopes;
  if (m.scopes.size() != m.parameters())
    throw Error(
        fmt::format("{} parameter scopes for {} parameters", m.scopes.size(), m.parameters()),
        {"formula"});
  m.loss = o.loss;
  if (pr.transform && o.loss == Loss::Log)
    throw Error(
        "a transform and the log loss cannot be combined (the log loss is the transform log2(y))",
        {"transform"});
  std::optional<Expression> t = pr.transform;
  if (o.loss == Loss::Log) t = parse_formula("log2(y)", {.variables = {"y"}});
  if (t) {
    for (const std::string& v : t->variables)
      if (v != "y" && std::find(m.formula.variables.begin(), m.formula.variables.end(), v) ==
                          m.formula.variables.end())
        throw Error("the transform uses '" + v + "', which is not a variable of the formula",
                    {"transform"});
    if (!t->parameters.empty()) throw Error("the transform cannot have parameters", {"transform"});
    m.fitted = substitute_variable(*t, "y", m.formula);
  } else {
    m.fitted = m.formula;
  }
  m.transform = t;
  m.fitted_columns = m.fitted.variables;
  m.structurally_linear = is_linear_in_parameters(m.fitted);
  m.constraints = pr.constraints;
  for (const Constraint& c : m.constraints) {
    if (c.kind == Constraint::Kind::parameters && c.lhs.parameters != m.formula.parameters)
      throw Error(
          "constraint '" + c.text + "' was parsed against other parameters than the formula's",
          {"constraints"});
    Expression d;
    if (c.kind == Constraint::Kind::derivative) {
      d = m.formula;
      const auto vi =
          std::find(d.variables.begin(), d.variables.end(), c.variable) - d.variables.begin();
      const int extra = static_cast<int>(d.parameters.size());
      d.parameters.push_back("d/d" + c.variable);
      d.parameter_values.push_back(0.0);
      for (Node& n : d.nodes)
        if (n.op == Op::Var && n.index == vi) n = Node::parameter(extra);
    }
    m.derivative_forms.push_back(std::move(d));
    m.constraint_linear.push_back(c.kind == Constraint::Kind::parameters
                                      ? is_linear_in_parameters(c.lhs)
                                      : is_linear_in_parameters(m.formula));
  }
  return m;
}

double lookup(const Constraint& c, const FitBlock& b, const std::string& name) {
  for (const auto& [n, v] : c.point)
    if (n == name) return v;
  for (const auto& [n, v] : b.context)
    if (n == name) return v;
  throw Error("constraint '" + c.text + "' needs a value for '" + name +
                  "' (set it in the point, e.g. f(" + name + " = 0)), block '" + b.label + "'",
              {"constraints"});
}

PreparedBlock prepare_block(const Model& m, const FitBlock& b) {
  PreparedBlock p;
  p.block = &b;
  const std::string where = "block '" + b.label + "'";
  if (b.columns.size() != m.formula.variables.size())
    throw Error(fmt::format("{} has {} columns but the formula has {} variables", where,
                            b.columns.size(), m.formula.variables.size()),
                {"data"});
  const std::size_t rows = b.target.size();
  for (std::size_t k = 0; k < b.columns.size(); ++k)
    if (b.columns[k].size() != rows)
      throw Error(fmt::format("{}: column '{}' has {} rows, the target {}", where,
                              m.formula.variables[k], b.columns[k].size(), rows),
                  {"data"});
  if (!b.weights.empty() && b.weights.size() != rows)
    throw Error(fmt::format("{}: {} weights for {} rows", where, b.weights.size(), rows),
                {"weights"});
  p.weights = b.weights.empty() ? std::vector<double>(rows, 1.0) : b.weights;
  for (std::size_t i = 0; i < rows; ++i) {
    if (!(p.weights[i] >= 0) || !std::isfinite(p.weights[i]))
      throw Error(fmt::format("weight {} in row {} of {} is {}", p.weights[i], i + 1, where,
                              p.weights[i] < 0 ? "negative" : "not finite"),
                  {"weights"});
    if (!std::isfinite(b.target[i]))
      throw Error(fmt::format("the target is not finite in row {} of {}", i + 1, where), {"data"});
    if (m.loss == Loss::Log && !(b.target[i] > 0))
      throw Error(fmt::format("the log loss needs positive targets; row {} of {} has {}", i + 1,
                              where, b.target[i]),
                  {"data"});
  }
  auto column_of = [&](const std::string& name) -> const double* {
    const auto k = std::find(m.formula.variables.begin(), m.formula.variables.end(), name) -
                   m.formula.variables.begin();
    return b.columns[static_cast<std::size_t>(k)].data();
  };
  for (const std::string& v : m.fitted_columns) p.columns.push_back(column_of(v));
  // The target in the fitted space: the transform (or log2) at y = target.
  if (m.transform) {
    std::vector<const double*> tc;
    for (const std::string& v : m.transform->variables)
      tc.push_back(v == "y" ? b.target.data() : column_of(v));
    p.target.resize(rows);
    if (rows > 0)
      evaluate(*m.transform, std::span<const double* const>(tc), std::span<double>(p.target),
               {.threads = 1});
    for (std::size_t i = 0; i < rows; ++i)
      if (!std::isfinite(p.target[i]))
        throw Error(
            fmt::format("the transform of the target is not finite in row {} of {}", i + 1, where),
            {"transform"});
  } else {
    p.target = b.target;
  }
  for (std::size_t k = 0; k < m.constraints.size(); ++k) {
    const Constraint& c = m.constraints[k];
    fit_detail::ConstraintInstance ci;
    ci.constraint = &c;
    ci.index = k;
    if (c.kind != Constraint::Kind::parameters)
      for (const std::string& v : m.formula.variables) ci.point.push_back(lookup(c, b, v));
    std::vector<double> rv;
    for (const std::string& v : c.rhs.variables) rv.push_back(lookup(c, b, v));
    ci.target = evaluate_scalar(c.rhs, rv);
    if (!std::isfinite(ci.target))
      throw Error("the right-hand side of constraint '" + c.text + "' is not finite in " + where,
                  {"constraints"});
    p.constraints.push_back(std::move(ci));
  }
  return p;
}

bool structural(FailureKind k) {
  return k == FailureKind::contradiction || k == FailureKind::singular ||
         k == FailureKind::not_linear || k == FailureKind::too_large || k == FailureKind::no_rows;
}

}  // namespace

void solve_fixed_form(const FixedFormOptions& options, const FixedFormProblem& problem,
                      FixedFormSummary* summary) {
  const auto t0 = std::chrono::steady_clock::now();
  if (!fit_minimises(options.loss))
    throw Error(
        "the fit minimises mse, log or max_abs, not " + std::string(loss_name(options.loss)),
        {"FixedFormOptions::loss"});
  std::string why;
  if (!options.is_valid(&why)) throw Error(why, {"fit options"});
  Model m = build_model(options, problem);
  if (problem.blocks.empty()) throw Error("no data to fit", {"data"});
  std::vector<PreparedBlock> blocks(problem.blocks.size());
  for (std::size_t b = 0; b < blocks.size(); ++b) blocks[b] = prepare_block(m, problem.blocks[b]);
  bool nonlinear_constraint = false;
  for (bool l : m.constraint_linear) nonlinear_constraint = nonlinear_constraint || !l;
  m.linear = m.structurally_linear;
  if (!m.linear)
    for (const PreparedBlock& b : blocks)
      if (b.rows() > 0) {
        m.linear = sampled_linear(m, b, m.formula.parameter_values);
        break;
      }
  if (nonlinear_constraint) m.linear = false;
  if (options.solver == SolverKind::linear && !m.linear)
    throw Error(
        nonlinear_constraint
            ? "the linear solver needs linear constraints"
            : "the fitted quantity is not linear in the parameters; use Levenberg-Marquardt",
        {"solver"});

  FixedFormSummary s;
  s.parameter_names = m.formula.parameters;
  s.scopes = m.scopes;
  const bool use_linear = m.linear && options.solver != SolverKind::levenberg_marquardt;
  s.linear = use_linear;
  s.solver = use_linear ? "linear least squares" : "Levenberg-Marquardt";
  if (options.loss == Loss::MaxAbs) s.solver += " + Lawson minimax";
  const bool any_global = std::count(m.scopes.begin(), m.scopes.end(), ParameterScope::global) > 0;
  const std::vector<double>& start = m.formula.parameter_values;
  std::vector<FailureKind> kinds(blocks.size(), FailureKind::none);
  if (!any_global || blocks.size() == 1) {
    s.blocks.resize(blocks.size());
    const std::size_t grain = std::max<std::size_t>(1, blocks.size() / 256);
    ProgressCounter progress(options.on_progress, blocks.size(), "blocks");
    parallel_for(
        blocks.size(), grain,
        [&](std::size_t begin, std::size_t end) {
          for (std::size_t b = begin; b < end; ++b) {
            s.blocks[b] = fit_detail::solve_block(m, blocks[b], options, start, &kinds[b]);
            progress.add();
          }
        },
        options.threads);
  } else {
    s.coupled = true;
    std::vector<std::vector<double>> starts(blocks.size(), start);
    fit_detail::Failure f;
    s.blocks = fit_detail::solve_coupled(m, blocks, options, starts, &f);
    if (f) throw Error(f.message, {"fit"});
    for (std::size_t b = 0; b < blocks.size(); ++b)
      if (!s.blocks[b].ok) kinds[b] = FailureKind::no_rows;
  }
  for (const BlockResult& r : s.blocks) s.failed_blocks += r.ok ? 0 : 1;
  // A failure that every block shares is a property of the problem, not of the data: an error.
  if (s.failed_blocks == s.blocks.size() && structural(kinds.front()) &&
      std::all_of(kinds.begin(), kinds.end(), [&](FailureKind k) { return k == kinds.front(); })) {
    const std::string& msg = s.blocks.front().failure;
    throw Error(s.blocks.size() == 1 ? msg : msg + " (in every block)", {"fit"});
  }
  s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  *summary = std::move(s);
}

std::optional<double> FixedFormSummary::global(const std::string& name) const {
  for (std::size_t j = 0; j < parameter_names.size(); ++j)
    if (parameter_names[j] == name && scopes[j] == ParameterScope::global) {
      for (const BlockResult& b : blocks)
        if (b.ok) return b.parameters[j];
      return blocks.empty() ? std::nullopt : std::optional<double>(blocks.front().parameters[j]);
    }
  return std::nullopt;
}

std::string FixedFormSummary::brief_report(const PrintOptions& print) const {
  double lo = INFINITY, hi = 0;
  for (const BlockResult& b : blocks)
    if (b.ok) {
      lo = std::min(lo, b.final_cost);
      hi = std::max(hi, b.final_cost);
    }
  std::string r = fmt::format("{}{}: {} block{} fitted, {} failed", solver,
                              coupled ? " (joint)" : "", blocks.size() - failed_blocks,
                              blocks.size() - failed_blocks == 1 ? "" : "s", failed_blocks);
  if (failed_blocks < blocks.size())
    r += lo == hi ? fmt::format(", final cost {:.6g}", lo)
                  : fmt::format(", final cost {:.6g} .. {:.6g}", lo, hi);
  r += fmt::format(" ({:.3f} s)\n", seconds);
  for (std::size_t j = 0; j < parameter_names.size(); ++j)
    if (scopes[j] == ParameterScope::global)
      if (auto v = global(parameter_names[j]))
        r += fmt::format("  {} = {}\n", parameter_names[j], format_number(*v, print));
  std::size_t listed = 0;
  for (const BlockResult& b : blocks) {
    if (b.ok) continue;
    if (++listed > 20) {
      r += fmt::format("  ... {} more failed blocks\n", failed_blocks - 20);
      break;
    }
    r += fmt::format("  failed: {}: {}\n", b.label, b.failure);
  }
  return r;
}

}  // namespace shaderfit
