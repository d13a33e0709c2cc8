#include "search/power_sum.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include <fmt/format.h>

#include "search/row_sample.hpp"
#include "shaderfit/fit/linear.hpp"

namespace shaderfit::search_detail {

namespace {

constexpr std::size_t kBeam = 32;
constexpr double kSift = 1e-6;  // 1 - R^2 by the normal equations worth a refit on the rows
constexpr int kExponents[] = {-2, -1, 1, 2};

// A power product: exponent per input (0: absent), multiples of 1/2 for the quotient M.
using Powers = std::vector<double>;

struct Dictionary {
  std::vector<Powers> powers;                // [0] is the constant
  std::vector<std::vector<double>> values;   // each power product over the rows
  std::vector<std::vector<double>> columns;  // the same scaled to unit norm
  std::vector<std::vector<double>> gram;     // columns' inner products
};

// x^e for e a multiple of 1/2 (x > 0 where it is not whole), by products: std::pow costs the
// seed task's short searches too much.
double half_power(double x, double e) {
  const double a = std::abs(e);
  const int whole = static_cast<int>(a);
  double v = 1;
  for (int i = 0; i < whole; ++i) v *= x;
  if (a - whole > 0) v *= std::sqrt(x);
  return e < 0 ? 1 / v : v;
}

double power_product(const std::vector<std::vector<double>>& x, const Powers& e, std::size_t r) {
  double v = 1;
  for (std::size_t k = 0; k < e.size(); ++k)
    if (e[k] != 0) v *= half_power(x[k][r], e[k]);
  return v;
}

Dictionary monomials(const std::vector<std::vector<double>>& x, std::size_t rows) {
  const std::size_t n = x.size();
  Dictionary d;
  d.powers.emplace_back(n, 0.0);
  for (std::size_t i = 0; i < n; ++i)
    for (int a : kExponents) {
      Powers one(n, 0.0);
      one[i] = a;
      d.powers.push_back(one);
      for (std::size_t j = i + 1; j < n; ++j)
        for (int b : kExponents) {
          Powers two = one;
          two[j] = b;
          d.powers.push_back(two);
        }
    }
  for (const Powers& e : d.powers) {
    std::vector<double> c(rows);
    double norm = 0;
    for (std::size_t r = 0; r < rows; ++r) {
      c[r] = power_product(x, e, r);
      norm += c[r] * c[r];
    }
    norm = std::sqrt(norm);
    d.values.push_back(c);
    for (double& v : c) v /= norm;
    d.columns.push_back(std::move(c));
  }
  const std::size_t m = d.columns.size();
  d.gram.assign(m, std::vector<double>(m));
  for (std::size_t a = 0; a < m; ++a)
    for (std::size_t b = a; b < m; ++b) {
      double s = 0;
      for (std::size_t r = 0; r < rows; ++r) s += d.columns[a][r] * d.columns[b][r];
      d.gram[a][b] = d.gram[b][a] = s;
    }
  return d;
}

// The Cholesky factor of the normal equations of the columns `set` (the constant, index 0,
// always among them) and the projection z of t on them: t's residual sum of squares is
// t.t - z.z, and a column more extends both by one row (extend()). false where singular.
struct Factor {
  std::array<std::array<double, kPowerSumTerms + 2>, kPowerSumTerms + 2> l{};
  std::array<double, kPowerSumTerms + 2> z{};
  std::size_t k = 0;
  double explained = 0;  // z.z
};

using Subset = std::array<std::size_t, kPowerSumTerms + 1>;

// f with the column c appended (the new row of L and of z); false where c depends on the others.
bool extend(const Dictionary& d, const std::vector<double>& h, const Subset& set, Factor& f,
            std::size_t c) {
  const std::size_t i = f.k;
  double square = d.gram[c][c];
  for (std::size_t j = 0; j < i; ++j) {
    double v = d.gram[c][set[j]];
    for (std::size_t q = 0; q < j; ++q) v -= f.l[i][q] * f.l[j][q];
    f.l[i][j] = v / f.l[j][j];
    square -= f.l[i][j] * f.l[i][j];
  }
  if (!(square > 1e-12)) return false;
  f.l[i][i] = std::sqrt(square);
  double v = h[c];
  for (std::size_t q = 0; q < i; ++q) v -= f.l[i][q] * f.z[q];
  f.z[i] = v / f.l[i][i];
  f.explained += f.z[i] * f.z[i];
  f.k = i + 1;
  return true;
}

struct Fit {
  std::vector<std::size_t> set;
  std::vector<double> coefficients;  // for the unscaled power products
  double unexplained = 1;            // 1 - R^2 of t
};

// 1 - R^2 of t by the unscaled power products of `set`, refitted by QR on the rows.
Fit refit(const Dictionary& d, const std::vector<double>& t, const std::vector<std::size_t>& set) {
  const std::size_t rows = t.size();
  std::vector<const double*> p;
  for (std::size_t c : set) p.push_back(d.values[c].data());
  Fit f;
  f.set = set;
  f.coefficients = solve_least_squares(p, t);
  double mean = 0;
  for (double v : t) mean += v;
  mean /= static_cast<double>(rows);
  double total = 0, left = 0;
  for (std::size_t r = 0; r < rows; ++r) {
    double g = 0;
    for (std::size_t j = 0; j < set.size(); ++j) g += f.coefficients[j] * p[j][r];
    left += (g - t[r]) * (g - t[r]);
    total += (t[r] - mean) * (t[r] - mean);
  }
  f.unexplained = total > 0 ? left / total : 1;
  if (!std::isfinite(f.unexplained)) f.unexplained = 1;
  return f;
}

// The fewest terms that explain t exactly (kPowerSumExact), by a beam search.
std::optional<Fit> sparse_exact_fit(const Dictionary& d, const std::vector<double>& t) {
  const std::size_t m = d.columns.size();
  std::vector<double> h(m);
  for (std::size_t c = 0; c < m; ++c) {
    double s = 0;
    for (std::size_t r = 0; r < t.size(); ++r) s += d.columns[c][r] * t[r];
    h[c] = s;
  }
  double tt = 0, mean = 0;
  for (double v : t) {
    tt += v * v;
    mean += v;
  }
  mean /= static_cast<double>(t.size());
  // The sum of squares about the mean, for the normal equations' 1 - R^2.
  const double spread = tt - mean * mean * static_cast<double>(t.size());
  if (!(spread > 0)) return std::nullopt;
  // A subset is the constant and up to kPowerSumTerms columns, packed 12 bits each in
  // ascending order into one key.
  static_assert(kPowerSumTerms * 12 <= 64);
  // Into `set`; returns the count (the constant included).
  const auto unpack_into = [](std::uint64_t key, Subset& set) {
    std::size_t k = 1;
    set[0] = 0;
    for (; key != 0; key >>= 12) set[k++] = static_cast<std::size_t>(key & 0xfff);
    return k;
  };
  const auto unpack = [&](std::uint64_t key) {
    Subset s{};
    const std::size_t k = unpack_into(key, s);
    return std::vector<std::size_t>(s.begin(), s.begin() + static_cast<std::ptrdiff_t>(k));
  };
  const auto pack = [](const std::vector<std::size_t>& set) {
    std::uint64_t key = 0;
    for (std::size_t i = set.size(); i-- > 1;) key = (key << 12) | set[i];
    return key;
  };
  if (m > 0xfff) return std::nullopt;
  std::vector<std::uint64_t> beam = {0};
  std::vector<std::pair<double, std::uint64_t>> next;
  for (std::size_t level = 1; level <= kPowerSumTerms; ++level) {
    next.clear();
    for (std::uint64_t key : beam) {
      Subset base{};
      const std::size_t k = unpack_into(key, base);
      Factor f;
      bool regular = true;
      for (std::size_t j = 0; j < k && regular; ++j) regular = extend(d, h, base, f, base[j]);
      if (!regular) continue;
      for (std::size_t c = 1; c < m; ++c) {
        if (std::find(base.begin(), base.begin() + static_cast<std::ptrdiff_t>(k), c) !=
            base.begin() + static_cast<std::ptrdiff_t>(k))
          continue;
        Factor g = f;
        if (!extend(d, h, base, g, c)) continue;
        std::vector<std::size_t> set(base.begin(), base.begin() + static_cast<std::ptrdiff_t>(k));
        set.insert(std::upper_bound(set.begin() + 1, set.end(), c), c);
        next.emplace_back(tt - g.explained, pack(set));
      }
    }
    std::sort(next.begin(), next.end(),
              [](const auto& a, const auto& b) { return a.second < b.second; });
    next.erase(std::unique(next.begin(), next.end(),
                           [](const auto& a, const auto& b) { return a.second == b.second; }),
               next.end());
    const std::size_t keep = std::min(kBeam, next.size());
    std::partial_sort(next.begin(), next.begin() + static_cast<std::ptrdiff_t>(keep), next.end());
    beam.clear();
    // The normal equations rank and sift; the rows decide (the normal equations' rounding
    // hides 1 - R^2 below about 1e-8).
    for (std::size_t i = 0; i < keep; ++i) {
      if (i < 3 && next[i].first <= kSift * spread) {
        Fit f = refit(d, t, unpack(next[i].second));
        if (f.unexplained <= kPowerSumExact) return f;
      }
      beam.push_back(next[i].second);
    }
  }
  return std::nullopt;
}

std::string number(double v) { return fmt::format("{:.17g}", v); }

// "x0^2 * sqrt(x1)" for exponents {2, 0.5}; "" for none.
std::string product_text(const Powers& e) {
  std::string out;
  for (std::size_t k = 0; k < e.size(); ++k) {
    const double a = std::abs(e[k]);
    if (e[k] <= 0) continue;
    const int whole = static_cast<int>(std::floor(a));
    const auto factor = [&](const std::string& f) { out += (out.empty() ? "" : " * ") + f; };
    const std::string name = "x" + std::to_string(k);
    if (whole == 1) factor(name);
    if (whole > 1) factor(name + "^" + std::to_string(whole));
    if (a - whole > 0) factor("sqrt(" + name + ")");
  }
  return out;
}

// The power product as a formula: "x0 * x1^2 / (x2)" (or "1").
std::string powers_text(const Powers& e) {
  Powers up(e.size()), down(e.size());
  for (std::size_t k = 0; k < e.size(); ++k) (e[k] > 0 ? up : down)[k] = std::abs(e[k]);
  const std::string num = product_text(up), den = product_text(down);
  if (den.empty()) return num.empty() ? "1" : num;
  return (num.empty() ? "1" : num) + " / (" + den + ")";
}

}  // namespace

std::optional<std::string> exact_power_sum(const SearchProblem& problem) {
  const SearchProblem s = evenly_spread_rows(problem, kPowerSumRows);
  const std::size_t rows = s.target.size();
  const std::size_t n = s.inputs.size();
  if (n < kPowerSumMinInputs || n > kPowerSumInputs || rows < 64) return std::nullopt;
  const auto usable = [](double v) { return std::isfinite(v) && v != 0; };
  if (!std::all_of(s.target.begin(), s.target.end(), usable)) return std::nullopt;
  bool positive = true;
  for (const auto& col : s.inputs) {
    if (!std::all_of(col.begin(), col.end(), usable)) return std::nullopt;
    positive = positive && std::all_of(col.begin(), col.end(), [](double v) { return v > 0; });
  }

  // M: log |y| against the log |x_k|, exponents rounded to halves (to integers where an input
  // takes negative values, whose square root is not real) and to integers; or M = 1.
  std::vector<std::vector<double>> logs(n + 1, std::vector<double>(rows, 1.0));
  std::vector<double> log_y(rows);
  for (std::size_t r = 0; r < rows; ++r) {
    for (std::size_t k = 0; k < n; ++k) logs[k + 1][r] = std::log(std::abs(s.inputs[k][r]));
    log_y[r] = std::log(std::abs(s.target[r]));
  }
  std::vector<const double*> lc;
  for (const auto& c : logs) lc.push_back(c.data());
  const std::vector<double> b = solve_least_squares(lc, log_y);
  Powers halves(n), wholes(n);
  for (std::size_t k = 0; k < n; ++k) {
    halves[k] = positive ? std::round(2 * b[k + 1]) / 2 : std::round(b[k + 1]);
    wholes[k] = std::round(b[k + 1]);
  }
  std::vector<Powers> quotients = {Powers(n, 0.0)};
  for (const Powers& m : {halves, wholes})
    if (std::find(quotients.begin(), quotients.end(), m) == quotients.end()) quotients.push_back(m);

  const Dictionary d = monomials(s.inputs, rows);
  std::optional<Fit> best;
  std::string best_text;
  for (const Powers& m : quotients)
    for (int p : {1, -1, 2, -2}) {
      std::vector<double> q(rows);
      for (std::size_t r = 0; r < rows; ++r) q[r] = s.target[r] / power_product(s.inputs, m, r);
      const double sign = q[0] < 0 ? -1 : 1;
      if ((p == 2 || p == -2) && !std::all_of(q.begin(), q.end(), [&](double v) {
            return v * sign > 0;
          }))
        continue;
      std::vector<double> t(rows);
      for (std::size_t r = 0; r < rows; ++r) t[r] = half_power(sign * q[r], p);
      if (p == 1 || p == -1)
        for (std::size_t r = 0; r < rows; ++r) t[r] *= sign;
      if (!std::all_of(t.begin(), t.end(), [](double v) { return std::isfinite(v); })) continue;
      std::optional<Fit> f = sparse_exact_fit(d, t);
      if (!f || (best && f->set.size() >= best->set.size())) continue;
      // The sum, then M and the power around it.
      std::string sum;
      double largest = 0;
      for (double c : f->coefficients) largest = std::max(largest, std::abs(c));
      for (std::size_t j = 0; j < f->set.size(); ++j) {
        const double c = f->coefficients[j];
        if (j == 0 && std::abs(c) <= 1e-13 * largest) continue;  // a constant at rounding level
        const std::string term = f->set[j] == 0 ? number(c)
                                                : "(" + number(c) + ") * " + powers_text(d.powers[f->set[j]]);
        sum += (sum.empty() ? "" : " + ") + term;
      }
      std::string text;
      switch (p) {
        case 1: text = "(" + sum + ")"; break;
        case -1: text = "1 / (" + sum + ")"; break;
        case 2: text = "sqrt(" + sum + ")"; break;
        default: text = "rsqrt(" + sum + ")"; break;
      }
      if (p == 2 || p == -2) text = number(sign) + " * " + text;
      text = "(" + powers_text(m) + ") * " + text;
      best = std::move(f);
      best_text = std::move(text);
    }
  if (!best) return std::nullopt;
  return best_text;
}

}  // namespace shaderfit::search_detail
