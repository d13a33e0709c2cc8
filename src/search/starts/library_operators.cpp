#include "search/starts/library_operators.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "search/starts/row_sample.hpp"

namespace shaderfit::search_detail {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kPi = std::numbers::pi;

// The monomial model needs its logarithms on nearly every row: rows with a zero input or target
// are left out, up to this share of them.
constexpr double kMonomialRows = 0.9;

// 1 - R^2 of q's least-squares fit by a constant and the columns, by modified Gram-Schmidt on the
// centred columns (twice, for orthogonality to rounding); a column that the others (or a
// constant) explain is dropped. NaN when q is constant or not finite.
double unexplained(const std::vector<std::vector<double>>& columns, const std::vector<double>& q) {
  const std::size_t n = q.size();
  if (n < 3) return kNaN;
  const auto centred = [n](const std::vector<double>& v) {
    double mean = 0;
    for (double x : v) mean += x;
    mean /= static_cast<double>(n);
    std::vector<double> c(n);
    for (std::size_t i = 0; i < n; ++i) c[i] = v[i] - mean;
    return c;
  };
  const auto dot = [n](const std::vector<double>& a, const std::vector<double>& b) {
    double s = 0;
    for (std::size_t i = 0; i < n; ++i) s += a[i] * b[i];
    return s;
  };
  std::vector<double> r = centred(q);
  const double total = dot(r, r);
  if (!(total > 0) || !std::isfinite(total)) return kNaN;
  std::vector<std::vector<double>> basis;
  for (const std::vector<double>& column : columns) {
    std::vector<double> u = centred(column);
    const double norm0 = std::sqrt(dot(u, u));
    if (!(norm0 > 0) || !std::isfinite(norm0)) continue;
    for (int pass = 0; pass < 2; ++pass)
      for (const std::vector<double>& b : basis) {
        const double p = dot(u, b);
        for (std::size_t i = 0; i < n; ++i) u[i] -= p * b[i];
      }
    const double norm = std::sqrt(dot(u, u));
    if (!(norm > 1e-9 * norm0)) continue;
    for (double& x : u) x /= norm;
    basis.push_back(std::move(u));
  }
  for (int pass = 0; pass < 2; ++pass)
    for (const std::vector<double>& b : basis) {
      const double p = dot(r, b);
      for (std::size_t i = 0; i < n; ++i) r[i] -= p * b[i];
    }
  return dot(r, r) / total;
}

// How well the simple models of the inputs explain q: the smaller 1 - R^2 of the linear model
// and of the monomial one (log |q| against the log |x_i|), NaN when neither applies.
double explained_by_simple_model(const std::vector<std::vector<double>>& inputs,
                                 const std::vector<double>& q) {
  const double linear = unexplained(inputs, q);
  std::vector<std::vector<double>> logs(inputs.size());
  std::vector<double> log_q;
  for (std::size_t i = 0; i < q.size(); ++i) {
    bool usable = q[i] != 0;
    for (const std::vector<double>& x : inputs) usable = usable && x[i] != 0;
    if (!usable) continue;
    for (std::size_t k = 0; k < inputs.size(); ++k)
      logs[k].push_back(std::log(std::fabs(inputs[k][i])));
    log_q.push_back(std::log(std::fabs(q[i])));
  }
  const double monomial =
      static_cast<double>(log_q.size()) >= kMonomialRows * static_cast<double>(q.size())
          ? unexplained(logs, log_q)
          : kNaN;
  if (std::isnan(linear)) return monomial;
  if (std::isnan(monomial)) return linear;
  return std::min(linear, monomial);
}

struct Candidate {
  Op op;
  double lo, hi;  // the function's range
  bool open;      // the range excludes its ends
  double (*inverse)(double);
};

bool program_calls(const reference::Program& p, Op op) {
  using reference::ProgramOp;
  return std::any_of(p.code.begin(), p.code.end(), [op](const reference::Instruction& in) {
    switch (in.op) {
      case ProgramOp::Asin: return op == Op::Asin;
      case ProgramOp::Acos: return op == Op::Acos;
      case ProgramOp::Atan: return op == Op::Atan;
      case ProgramOp::Atan2: return op == Op::Atan2;
      case ProgramOp::Tanh: return op == Op::Tanh;
      case ProgramOp::Erf:
      case ProgramOp::Erfc: return op == Op::Erf;
      default: return false;
    }
  });
}

}  // namespace

double inverse_erf(double y) {
  if (std::isnan(y) || std::fabs(y) > 1) return kNaN;
  if (std::fabs(y) == 1) return std::copysign(std::numeric_limits<double>::infinity(), y);
  const double a = std::fabs(y);
  double x = 0;
  if (a <= 0.5) {
    // Newton's method on erf(x) = a from the first term of erf's series.
    x = a * std::sqrt(kPi) / 2;
    for (int i = 0; i < 50; ++i) {
      const double step = (std::erf(x) - a) / (2 / std::sqrt(kPi) * std::exp(-x * x));
      x -= step;
      if (std::fabs(step) <= 1e-16 * x) break;
    }
  } else {
    // On log erfc(x) = log(1 - a), nearly a parabola in x: 1 - a is exact here, and the
    // logarithm keeps the steps good far in the tail.
    const double target = std::log(1 - a);
    x = std::sqrt(-target);
    for (int i = 0; i < 100; ++i) {
      const double e = std::erfc(x);
      const double slope = -2 / std::sqrt(kPi) * std::exp(-x * x) / e;
      const double step = (std::log(e) - target) / slope;
      x = std::max(x - step, 0.5 * x);
      if (std::fabs(step) <= 1e-16 * x) break;
    }
  }
  return std::copysign(x, y);
}

std::vector<Op> suggested_library_operators(const SearchProblem& p) {
  static const Candidate kCandidates[] = {
      {Op::Asin, -kPi / 2, kPi / 2, false, [](double y) { return std::sin(y); }},
      {Op::Acos, 0, kPi, false, [](double y) { return std::cos(y); }},
      {Op::Atan, -kPi / 2, kPi / 2, true, [](double y) { return std::tan(y); }},
      {Op::Atan2, -kPi, kPi, false, [](double y) { return std::tan(y); }},
      {Op::Tanh, -1, 1, true, [](double y) { return std::atanh(y); }},
      {Op::Erf, -1, 1, true, inverse_erf},
  };
  std::vector<Op> out;
  // A function of one input is what a user approximates such a function by: its exact form is
  // the function itself, at 17 to 33 instructions, and the operator only spends the search's
  // mutations (the yardstick's acos cases lost 3 of their wins to it).
  if (p.inputs.size() < 2) return out;
  if (p.reference)
    for (const Candidate& c : kCandidates)
      if (program_calls(p.reference->program, c.op)) out.push_back(c.op);

  // At most kLibraryProbeRows rows, evenly spread.
  const SearchProblem sample = evenly_spread_rows(p, kLibraryProbeRows);
  const std::size_t n = sample.target.size();
  if (n < 16 || p.inputs.empty()) return out;
  // The simple models read the inputs and their sines and cosines: arcsin(n sin(theta)).
  std::vector<std::vector<double>> inputs = sample.inputs;
  for (const std::vector<double>& x : sample.inputs)
    for (double (*wave)(double) :
         {static_cast<double (*)(double)>(std::sin), static_cast<double (*)(double)>(std::cos)}) {
      std::vector<double> w(n);
      std::transform(x.begin(), x.end(), w.begin(), wave);
      inputs.push_back(std::move(w));
    }
  const std::vector<double>& y = sample.target;
  const auto [y_lo, y_hi] = std::minmax_element(y.begin(), y.end());
  const double target_score = explained_by_simple_model(inputs, y);
  if (!(target_score > 0)) return out;  // constant, or a simple model already explains it exactly
  std::vector<double> z(n);
  for (const Candidate& c : kCandidates) {
    if (std::find(out.begin(), out.end(), c.op) != out.end()) continue;
    const bool inside = c.open ? *y_lo > c.lo && *y_hi < c.hi : *y_lo >= c.lo && *y_hi <= c.hi;
    if (!inside) continue;
    // atan2 only where atan's range does not hold the target.
    if (c.op == Op::Atan2 && std::max(-*y_lo, *y_hi) <= kPi / 2) continue;
    bool finite = true;
    for (std::size_t i = 0; i < n; ++i) {
      z[i] = c.inverse(y[i]);
      finite = finite && std::isfinite(z[i]);
    }
    if (!finite) continue;
    const double score = explained_by_simple_model(inputs, z);
    if (score <= kExplained && score * kBetter <= target_score) out.push_back(c.op);
  }
  // In the order of the list.
  std::vector<Op> ordered;
  for (const Candidate& c : kCandidates)
    if (std::find(out.begin(), out.end(), c.op) != out.end()) ordered.push_back(c.op);
  return ordered;
}

}  // namespace shaderfit::search_detail
