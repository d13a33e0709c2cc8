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

bool program_calls(const reference::Program& p, Op op) {
  using reference::ProgramOp;
  return std::any_of(p.code.begin(), p.code.end(), [op](const reference::Instruction& in) {
    if (in.op == ProgramOp::Operator) return static_cast<Op>(in.index) == op;
    return in.op == ProgramOp::Erfc && op == Op::Erf;
  });
}

}  // namespace

std::vector<Op> suggested_library_operators(const SearchProblem& p) {
  // The operators that can be undone (expr/op.hpp's op_inverse), in enum order.
  struct Candidate {
    Op op;
    OpInverse range;
  };
  std::vector<Candidate> candidates;
  for (int i = 0; i < kOpCount; ++i)
    if (const OpInverse r = op_inverse(static_cast<Op>(i)); r.invertible)
      candidates.push_back({static_cast<Op>(i), r});
  std::vector<Op> out;
  // A function of one input is what a user approximates such a function by: its exact form is
  // the function itself, at 17 to 33 instructions, and the operator only spends the search's
  // mutations (the yardstick's acos cases lost 3 of their wins to it).
  if (p.inputs.size() < 2) return out;
  if (p.reference)
    for (const Candidate& c : candidates)
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
  for (const Candidate& c : candidates) {
    if (std::find(out.begin(), out.end(), c.op) != out.end()) continue;
    const OpInverse& r = c.range;
    const bool inside = r.open ? *y_lo > r.lo && *y_hi < r.hi : *y_lo >= r.lo && *y_hi <= r.hi;
    if (!inside) continue;
    // atan2 only where atan's range does not hold the target.
    if (c.op == Op::Atan2 && std::max(-*y_lo, *y_hi) <= kPi / 2) continue;
    bool finite = true;
    for (std::size_t i = 0; i < n; ++i) {
      z[i] = op_inverse_value(c.op, y[i]);
      finite = finite && std::isfinite(z[i]);
    }
    if (!finite) continue;
    const double score = explained_by_simple_model(inputs, z);
    if (score <= kExplained && score * kBetter <= target_score) out.push_back(c.op);
  }
  // In the order of the list.
  std::vector<Op> ordered;
  for (const Candidate& c : candidates)
    if (std::find(out.begin(), out.end(), c.op) != out.end()) ordered.push_back(c.op);
  return ordered;
}

}  // namespace shaderfit::search_detail
