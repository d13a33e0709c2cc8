#include "search/operator_probe.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "search/row_sample.hpp"
#include "shaderfit/fit/linear.hpp"

namespace shaderfit::search_detail {

namespace {

// Each probe enumerates this many candidates in a search of 10 s or more (on one thread, about a
// quarter of a second): levels 2 to 3 of the arithmetic, where r F sin(theta) shows.
constexpr std::int64_t kProbeCandidates = 3'000'000;
// A clock stop as well, for machines much slower than the budget above assumes; counted runs
// end before it.
constexpr double kProbeTimeLimit = 5.0;

std::vector<FrontMember> probe_front(const SearchOptions& options, const SearchProblem& rows,
                                     const std::vector<Op>& ops) {
  SearchOptions o;
  o.loss = options.loss;
  o.cost = options.cost;
  o.max_power = options.max_power;
  o.literals = options.literals;
  o.seed = options.seed;
  o.symmetry = options.symmetry;
  o.operators = ops;
  o.evolution_operators = {};
  o.evolve = false;
  o.threads = 1;
  o.device = ComputeDevice::Cpu;
  o.max_enumeration_share = 1;
  // Short searches probe less (a tenth at most of what a 10 s search spends).
  o.max_candidates = static_cast<std::int64_t>(static_cast<double>(kProbeCandidates) *
                                               std::clamp(options.time_limit_s / 10, 0.1, 1.0));
  o.time_limit_s = kProbeTimeLimit;
  SearchSummary s;
  run_search(o, rows, &s);
  return s.front;
}

// The residual sum of squares of y's least-squares fit by the columns (weights as the problem's).
double residual(const std::vector<std::vector<double>>& columns, const SearchProblem& p) {
  std::vector<const double*> c;
  for (const auto& col : columns) c.push_back(col.data());
  const std::vector<double> k = solve_least_squares(c, p.target, p.weights);
  double sum = 0;
  for (std::size_t i = 0; i < p.target.size(); ++i) {
    double f = 0;
    for (std::size_t j = 0; j < columns.size(); ++j) f += k[j] * columns[j][i];
    const double w = p.weights.empty() ? 1.0 : p.weights[i];
    sum += w * (f - p.target[i]) * (f - p.target[i]);
  }
  return sum;
}

// One input's trace in the target: over an input that spans at least pi (half a period, where
// a sine turns and a low polynomial does not follow it; over less, smooth odd functions such as
// atan pass as sines), y ~ a + b sin x + c cos x fits at most kTrigRatio of the residual of
// y ~ a + b x + c x^2 (the same number of coefficients) and explains at least kTrigShare of y's
// variance. The other inputs act as noise on both fits alike; r F sin(theta) and
// q (E + B v sin(theta)) over theta in [1, 5] show it (ratios 0.77 and 0.94), the AI-Feynman
// functions without a periodic part do not (0.999 and above).
constexpr double kTrigRatio = 0.99;
constexpr double kTrigShare = 0.3;

bool one_input_is_periodic(const SearchProblem& p) {
  const std::size_t n = p.target.size();
  const std::vector<double> one(n, 1.0);
  const double total = residual({one}, p);
  if (!(total > 0)) return false;
  for (const std::vector<double>& x : p.inputs) {
    const auto [lo, hi] = std::minmax_element(x.begin(), x.end());
    if (!(*hi - *lo >= std::numbers::pi)) continue;
    std::vector<double> x2(n), s(n), c(n);
    for (std::size_t i = 0; i < n; ++i) {
      x2[i] = x[i] * x[i];
      s[i] = std::sin(x[i]);
      c[i] = std::cos(x[i]);
    }
    const double trig = residual({one, s, c}, p);
    const double poly = residual({one, x, x2}, p);
    if (trig <= kTrigRatio * poly && trig <= (1 - kTrigShare) * total) return true;
  }
  return false;
}

bool uses_any(const Expression& e, const std::vector<Op>& ops) {
  return std::any_of(e.nodes.begin(), e.nodes.end(), [&](const Node& n) {
    return std::find(ops.begin(), ops.end(), n.op) != ops.end();
  });
}

}  // namespace

std::span<const OperatorGroup> probed_operator_groups() {
  static const std::vector<OperatorGroup> groups = {
      {"trigonometric", {Op::Sin, Op::Cos}, one_input_is_periodic},
  };
  return groups;
}

std::vector<Op> probe_operator_groups(const SearchOptions& options, const SearchProblem& problem,
                                      const std::vector<Op>& base,
                                      std::span<const OperatorGroup> groups) {
  std::vector<Op> out;
  if (groups.empty() || problem.target.size() < 16) return out;
  const SearchProblem rows = evenly_spread_rows(problem, kProbeRows);
  // The arithmetic of `base` only: its other functions multiply the candidates of every level
  // without telling whether a group helps.
  std::vector<Op> arithmetic;
  for (Op op : base)
    if (op == Op::Add || op == Op::Sub || op == Op::Mul || op == Op::Div || op == Op::IPow)
      arithmetic.push_back(op);
  const std::vector<FrontMember> plain = probe_front(options, rows, arithmetic);
  const auto best_at = [&](double cost) {
    double best = std::numeric_limits<double>::infinity();
    for (const FrontMember& m : plain)
      if (m.cost <= cost) best = std::min(best, m.loss);
    return best;
  };
  for (const OperatorGroup& g : groups) {
    std::vector<Op> added;
    for (Op op : g.ops)
      if (std::find(base.begin(), base.end(), op) == base.end()) added.push_back(op);
    if (added.empty()) continue;
    std::vector<Op> ops = arithmetic;
    ops.insert(ops.end(), added.begin(), added.end());
    const std::vector<FrontMember> with = probe_front(options, rows, ops);
    if (g.signal != nullptr && g.signal(problem)) {
      for (Op op : added)
        if (std::find(out.begin(), out.end(), op) == out.end()) out.push_back(op);
      continue;
    }
    const bool gains = std::any_of(with.begin(), with.end(), [&](const FrontMember& m) {
      return uses_any(m.expression, added) && m.loss < kProbeGain * best_at(m.cost);
    });
    if (gains)
      for (Op op : added)
        if (std::find(out.begin(), out.end(), op) == out.end()) out.push_back(op);
  }
  return out;
}

}  // namespace shaderfit::search_detail
