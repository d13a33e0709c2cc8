#include "search/starts/operator_probe.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>

#include "search/starts/row_sample.hpp"
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

// Where the data turns like a sine, over an angle z that is an input, the product, ratio or
// difference of two inputs, or (up to four inputs) x_i x_j / x_k. The target is first divided by
// a power product of the inputs that z does not use, fitted to log|y| beside a step function of
// z (so z's own part does not bias the exponents), with exponents within 0.15 of a multiple of
// 1/2 rounded to it, refitted without the fifth of the rows it misses most (a zero of y):
// r F cos(theta) becomes C cos(theta). On that quotient q, the angle is taken
// as periodic when one of these holds:
//  - strong: q ~ a + b sin(w z) + c cos(w z), w in {1/2, 1, 2}, fits within kTrigStrong of the
//    residual of q ~ a + b z + c z^2 (p cos(theta) / r^2 over theta in [1, 3], 1e-28);
//  - a full period: for a frequency w scanned where w z spans at least 2 pi, one or two
//    harmonics fit within kTrigPeriod of a polynomial with as many coefficients (degree 2 or 4)
//    and leave at most kTrigPeriodShare of q's variance (sin(E t / h)^2: 1e-5; cos(w t) +
//    alpha cos(w t)^2: 0.2 to 0.36), z spanning at most kTrigTail interquartile ranges;
//  - half a period of one input (the target itself, no quotient): over an input that spans at
//    least pi, y ~ a + b sin x + c cos x fits within kTrigRatio of the quadratic and explains at
//    least kTrigShare of y's variance (q (E + B v sin(theta)): 0.93).
// On the 100 AI-Feynman equations (512 rows, four draws) this holds for 12 or 13 of the 18 with
// sin or cos and for none of the others but one in one draw (the half-period test, as before);
// a smooth monotone function (atan over less than half a period) passes none.
constexpr double kTrigStrong = 1e-3;
constexpr double kTrigPeriod = 0.4;
// The most z may span, in interquartile ranges, for the period test.
constexpr double kTrigTail = 8;
constexpr double kTrigPeriodShare = 0.5;
constexpr double kTrigRatio = 0.99;
constexpr double kTrigShare = 0.3;
constexpr std::size_t kTrigRows = 512;
constexpr std::size_t kTrigBins = 16;
constexpr int kTrigFrequencies = 100;  // geometric, 0.2 to 20

struct Angle {
  std::vector<std::size_t> uses;  // the inputs z is made of
  std::vector<double> z;
};

std::vector<Angle> candidate_angles(const std::vector<std::vector<double>>& x) {
  const std::size_t n = x.size();
  const std::size_t rows = n == 0 ? 0 : x[0].size();
  const auto nonzero = [&](std::size_t k) {
    return std::none_of(x[k].begin(), x[k].end(), [](double v) { return v == 0; });
  };
  std::vector<Angle> out;
  const auto add = [&](std::vector<std::size_t> uses, auto&& f) {
    Angle a{std::move(uses), std::vector<double>(rows)};
    for (std::size_t r = 0; r < rows; ++r) a.z[r] = f(r);
    out.push_back(std::move(a));
  };
  for (std::size_t i = 0; i < n; ++i) add({i}, [&](std::size_t r) { return x[i][r]; });
  if (n > 6) return out;  // pairs of many inputs: too many angles to test without false alarms
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) {
      add({i, j}, [&](std::size_t r) { return x[i][r] * x[j][r]; });
      add({i, j}, [&](std::size_t r) { return x[i][r] - x[j][r]; });
      if (nonzero(j)) add({i, j}, [&](std::size_t r) { return x[i][r] / x[j][r]; });
      if (nonzero(i)) add({i, j}, [&](std::size_t r) { return x[j][r] / x[i][r]; });
    }
  if (n > 4) return out;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j)
      for (std::size_t k = 0; k < n; ++k)
        if (k != i && k != j && nonzero(k))
          add({i, j, k}, [&](std::size_t r) { return x[i][r] * x[j][r] / x[k][r]; });
  return out;
}

// y divided by the power product of the inputs z does not use (see above); y itself where the
// quotient is not defined (a zero input, mostly zero targets).
std::vector<double> quotient(const SearchProblem& p, const Angle& a) {
  const std::size_t n = p.target.size();
  std::vector<std::size_t> others;
  for (std::size_t k = 0; k < p.inputs.size(); ++k)
    if (std::find(a.uses.begin(), a.uses.end(), k) == a.uses.end()) others.push_back(k);
  if (others.empty()) return p.target;
  for (std::size_t k : others)
    if (std::any_of(p.inputs[k].begin(), p.inputs[k].end(), [](double v) { return v == 0; }))
      return p.target;
  double top = 0;
  for (double y : p.target) top = std::max(top, std::abs(y));
  std::vector<std::size_t> used;
  for (std::size_t r = 0; r < n; ++r)
    if (std::abs(p.target[r]) > 1e-12 * top) used.push_back(r);
  if (used.size() < std::max<std::size_t>(n / 2, 4 * (kTrigBins + others.size()))) return p.target;
  std::vector<double> sorted = a.z;
  std::sort(sorted.begin(), sorted.end());
  const auto bin = [&](double z) {
    const auto at = std::upper_bound(sorted.begin(), sorted.end(), z) - sorted.begin();
    return std::min<std::size_t>(static_cast<std::size_t>(at) * kTrigBins / n, kTrigBins - 1);
  };
  std::vector<std::vector<double>> columns(kTrigBins + others.size(),
                                           std::vector<double>(used.size()));
  std::vector<double> log_y(used.size());
  for (std::size_t u = 0; u < used.size(); ++u) {
    const std::size_t r = used[u];
    columns[bin(a.z[r])][u] = 1;
    for (std::size_t k = 0; k < others.size(); ++k)
      columns[kTrigBins + k][u] = std::log(std::abs(p.inputs[others[k]][r]));
    log_y[u] = std::log(std::abs(p.target[r]));
  }
  std::vector<const double*> c;
  for (const auto& col : columns) c.push_back(col.data());
  std::vector<double> k = solve_least_squares(c, log_y);
  // Again without the fifth of the rows the fit misses most: near a zero of the target, log|y|
  // falls far below its bin's step and would tilt the exponents.
  std::vector<double> miss(used.size());
  for (std::size_t u = 0; u < used.size(); ++u) {
    double f = 0;
    for (std::size_t j = 0; j < columns.size(); ++j) f += k[j] * columns[j][u];
    miss[u] = std::abs(f - log_y[u]);
  }
  std::vector<double> order = miss;
  const auto cut = order.begin() + static_cast<std::ptrdiff_t>(order.size() * 4 / 5);
  std::nth_element(order.begin(), cut, order.end());
  std::vector<double> keep(used.size());
  for (std::size_t u = 0; u < used.size(); ++u) keep[u] = miss[u] <= *cut ? 1.0 : 0.0;
  k = solve_least_squares(c, log_y, keep);
  std::vector<double> q = p.target;
  for (std::size_t o = 0; o < others.size(); ++o) {
    double e = k[kTrigBins + o];
    const double half = std::round(2 * e) / 2;
    if (std::abs(e - half) <= 0.15) e = half;
    if (e == 0) continue;
    for (std::size_t r = 0; r < n; ++r) q[r] /= std::pow(std::abs(p.inputs[others[o]][r]), e);
  }
  return q;
}

bool angle_is_periodic(const SearchProblem& rows, const Angle& a) {
  const std::size_t n = rows.target.size();
  const std::vector<double> one(n, 1.0);
  SearchProblem q = rows;
  q.target = quotient(rows, a);
  if (!std::all_of(q.target.begin(), q.target.end(), [](double v) { return std::isfinite(v); }))
    return false;
  const double total = residual({one}, q);
  if (!(total > 0)) return false;
  std::vector<double> z2(n), z3(n), z4(n);
  for (std::size_t r = 0; r < n; ++r) {
    z2[r] = a.z[r] * a.z[r];
    z3[r] = z2[r] * a.z[r];
    z4[r] = z2[r] * z2[r];
  }
  const double quadratic = residual({one, a.z, z2}, q);
  const double quartic = residual({one, a.z, z2, z3, z4}, q);
  std::vector<double> s1(n), c1(n), s2(n), c2(n);
  const auto harmonics = [&](double w) {
    for (std::size_t r = 0; r < n; ++r) {
      s1[r] = std::sin(w * a.z[r]);
      c1[r] = std::cos(w * a.z[r]);
      s2[r] = 2 * s1[r] * c1[r];
      c2[r] = c1[r] * c1[r] - s1[r] * s1[r];
    }
  };
  for (double w : {1.0, 0.5, 2.0}) {
    harmonics(w);
    if (residual({one, s1, c1}, q) <= kTrigStrong * quadratic) return true;
  }
  const auto [lo, hi] = std::minmax_element(a.z.begin(), a.z.end());
  const double span = *hi - *lo;
  std::vector<double> sorted = a.z;
  std::sort(sorted.begin(), sorted.end());
  const double quartiles = sorted[n * 3 / 4] - sorted[n / 4];
  // A long-tailed angle (a ratio whose divisor nears 0) defeats any polynomial; a wave is no
  // better a guess there.
  for (int f = 0; f < kTrigFrequencies && span <= kTrigTail * quartiles; ++f) {
    const double w = 0.2 * std::pow(100.0, f / double(kTrigFrequencies - 1));
    if (!(w * span >= 2 * std::numbers::pi)) continue;
    harmonics(w);
    const double one_wave = residual({one, s1, c1}, q);
    if (one_wave <= kTrigPeriod * quadratic && one_wave <= kTrigPeriodShare * total) return true;
    const double two_waves = residual({one, s1, c1, s2, c2}, q);
    if (two_waves <= kTrigPeriod * quartic && two_waves <= kTrigPeriodShare * total) return true;
  }
  if (a.uses.size() == 1 && span >= std::numbers::pi) {
    const double all = residual({one}, rows);
    harmonics(1.0);
    const double trig = residual({one, s1, c1}, rows);
    const double poly = residual({one, a.z, z2}, rows);
    if (trig <= kTrigRatio * poly && trig <= (1 - kTrigShare) * all) return true;
  }
  return false;
}

bool some_angle_is_periodic(const SearchProblem& p) {
  if (p.target.size() < 4 * kTrigBins) return false;
  const SearchProblem rows = evenly_spread_rows(p, kTrigRows);
  for (const Angle& a : candidate_angles(rows.inputs))
    if (angle_is_periodic(rows, a)) return true;
  return false;
}

bool uses_any(const Expression& e, const std::vector<Op>& ops) {
  return std::any_of(e.nodes.begin(), e.nodes.end(), [&](const Node& n) {
    return std::find(ops.begin(), ops.end(), n.op) != ops.end();
  });
}

}  // namespace

std::span<const OperatorGroup> probed_operator_groups() {
  static const std::vector<OperatorGroup> groups = [] {
    std::vector<Op> periodic;
    for (int i = 0; i < kOpCount; ++i)
      if (is_periodic(static_cast<Op>(i))) periodic.push_back(static_cast<Op>(i));
    return std::vector<OperatorGroup>{{"trigonometric", periodic, some_angle_is_periodic}};
  }();
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
  // The enumeration without the groups, run only when a group's signal does not decide.
  std::optional<std::vector<FrontMember>> plain_front;
  const auto best_at = [&](double cost) {
    if (!plain_front) plain_front = probe_front(options, rows, arithmetic);
    const std::vector<FrontMember>& plain = *plain_front;
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
    if (g.signal != nullptr && g.signal(problem)) {
      for (Op op : added)
        if (std::find(out.begin(), out.end(), op) == out.end()) out.push_back(op);
      continue;
    }
    std::vector<Op> ops = arithmetic;
    ops.insert(ops.end(), added.begin(), added.end());
    const std::vector<FrontMember> with = probe_front(options, rows, ops);
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
