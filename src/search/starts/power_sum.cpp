#include "search/starts/power_sum.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "search/starts/row_sample.hpp"
#include "shaderfit/fit/linear.hpp"

namespace shaderfit::search_detail {

namespace {

constexpr std::size_t kBeam = 32;
constexpr double kSift = 1e-6;  // 1 - R^2 by the normal equations worth a refit on the rows
constexpr int kExponents[] = {-2, -1, 1, 2};
// An exponent of M this far from an integer is tried at both integers beside it, for the
// kUnsureInputs inputs farthest.
constexpr double kUnsureExponent = 0.1;
constexpr std::size_t kUnsureInputs = 2;
constexpr double kMostQuotientPower = 8;
// The transforms t = (y / M)^p tried.
constexpr double kPowers[] = {1, -1, 2, -2, 0.5, -0.5};

// A power product: exponent per input (0: absent), multiples of 1/2 for the quotient M.
using Powers = std::vector<double>;

// x^e for e a multiple of 1/2 (x > 0 where it is not whole), by products: std::pow costs the
// short searches too much.
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

// [0] the constant, then the power products of one and of two inputs with exponents from
// kExponents.
std::vector<Powers> monomials(std::size_t n) {
  std::vector<Powers> out = {Powers(n, 0.0)};
  for (std::size_t i = 0; i < n; ++i)
    for (int a : kExponents) {
      Powers one(n, 0.0);
      one[i] = a;
      out.push_back(one);
      for (std::size_t j = i + 1; j < n; ++j)
        for (int b : kExponents) {
          Powers two = one;
          two[j] = b;
          out.push_back(two);
        }
    }
  return out;
}

// The columns one transform t is fitted by (the monomials, [0] the constant, and for the
// logarithm the log2 |x_k|). Their inner products, scaled to unit norm, are computed when the
// beam first reads them.
class Columns {
 public:
  Columns(std::vector<const std::vector<double>*> columns, const std::vector<double>& t)
      : values_(std::move(columns)) {
    const std::size_t rows = t.size();
    norms_.resize(values_.size());
    t_dots_.resize(values_.size());
    for (std::size_t c = 0; c < values_.size(); ++c) {
      double nn = 0, nt = 0;
      for (std::size_t r = 0; r < rows; ++r) {
        nn += (*values_[c])[r] * (*values_[c])[r];
        nt += (*values_[c])[r] * t[r];
      }
      norms_[c] = std::sqrt(nn);
      t_dots_[c] = nt / norms_[c];
    }
    gram_.resize(values_.size());
  }

  std::size_t size() const { return values_.size(); }
  const std::vector<double>& values(std::size_t c) const { return *values_[c]; }
  // t's inner product with the scaled column c.
  double t_dot(std::size_t c) const { return t_dots_[c]; }
  bool usable(std::size_t c) const { return norms_[c] > 0 && std::isfinite(norms_[c]); }
  // The scaled columns' inner products with column a.
  const std::vector<double>& gram_row(std::size_t a) {
    std::vector<double>& g = gram_[a];
    if (g.empty()) {
      g.resize(values_.size());
      const std::vector<double>& va = *values_[a];
      for (std::size_t c = 0; c < values_.size(); ++c) {
        const std::vector<double>& vc = *values_[c];
        double s = 0;
        for (std::size_t r = 0; r < va.size(); ++r) s += va[r] * vc[r];
        g[c] = s / (norms_[a] * norms_[c]);
      }
    }
    return g;
  }

 private:
  std::vector<const std::vector<double>*> values_;
  std::vector<double> norms_, t_dots_;
  std::vector<std::vector<double>> gram_;
};

using Subset = std::array<std::size_t, kPowerSumTerms + 2>;  // one spare: a level's new column

// The Cholesky factor of the normal equations of the scaled columns `set` (the constant, index
// 0, always among them) and the projection z of t on them: t's residual sum of squares is
// t.t - z.z, and a column more extends both by one row.
struct Factor {
  std::array<std::array<double, kPowerSumTerms + 2>, kPowerSumTerms + 2> l{};
  std::array<double, kPowerSumTerms + 2> z{};
  std::size_t k = 0;
  double explained = 0;  // z.z
};

// f with the column c appended; false where c depends on the others.
bool extend(Columns& d, const Subset& set, Factor& f, std::size_t c) {
  const std::size_t i = f.k;
  double square = 1;
  for (std::size_t j = 0; j < i; ++j) {
    double v = d.gram_row(set[j])[c];
    for (std::size_t q = 0; q < j; ++q) v -= f.l[i][q] * f.l[j][q];
    f.l[i][j] = v / f.l[j][j];
    square -= f.l[i][j] * f.l[i][j];
  }
  if (!(square > 1e-12)) return false;
  f.l[i][i] = std::sqrt(square);
  double v = d.t_dot(c);
  for (std::size_t q = 0; q < i; ++q) v -= f.l[i][q] * f.z[q];
  f.z[i] = v / f.l[i][i];
  f.explained += f.z[i] * f.z[i];
  f.k = i + 1;
  return true;
}

struct Fit {
  std::vector<std::size_t> set;
  std::vector<double> coefficients;  // for the unscaled columns
  double unexplained = 1;            // 1 - R^2 of t
};

// 1 - R^2 of t by the unscaled columns of `set`, refitted by QR on the rows.
Fit refit(const Columns& d, const std::vector<double>& t, const std::vector<std::size_t>& set) {
  const std::size_t rows = t.size();
  std::vector<const double*> p;
  for (std::size_t c : set) p.push_back(d.values(c).data());
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

// The fewest columns that explain t exactly (kPowerSumExact), by a beam search.
std::optional<Fit> sparse_exact_fit(Columns& d, const std::vector<double>& t) {
  const std::size_t m = d.size();
  if (m > 0xfff) return std::nullopt;
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
  const auto unpack_into = [](std::uint64_t key, Subset& set) {
    std::size_t k = 1;
    set[0] = 0;
    for (; key != 0; key >>= 12) set[k++] = static_cast<std::size_t>(key & 0xfff);
    return k;
  };
  const auto pack = [](const Subset& set, std::size_t k) {
    std::uint64_t key = 0;
    for (std::size_t i = k; i-- > 1;) key = (key << 12) | set[i];
    return key;
  };
  std::vector<std::uint64_t> beam = {0};
  std::vector<std::pair<double, std::uint64_t>> next;
  for (std::size_t level = 1; level <= kPowerSumTerms; ++level) {
    next.clear();
    for (std::uint64_t key : beam) {
      Subset base{};
      const std::size_t k = unpack_into(key, base);
      Factor f;
      bool regular = true;
      for (std::size_t j = 0; j < k && regular; ++j) regular = extend(d, base, f, base[j]);
      if (!regular) continue;
      const auto end = base.begin() + static_cast<std::ptrdiff_t>(k);
      for (std::size_t c = 1; c < m; ++c) {
        if (!d.usable(c) || std::find(base.begin(), end, c) != end) continue;
        Factor g = f;
        if (!extend(d, base, g, c)) continue;
        // base with c in its place (base[1..k) ascending).
        Subset s = base;
        std::size_t at = k;
        for (; at > 1 && s[at - 1] > c; --at) s[at] = s[at - 1];
        s[at] = c;
        next.emplace_back(tt - g.explained, pack(s, k + 1));
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
        Subset s{};
        const std::size_t k = unpack_into(next[i].second, s);
        Fit f = refit(
            d, t, std::vector<std::size_t>(s.begin(), s.begin() + static_cast<std::ptrdiff_t>(k)));
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

// The fitted sum as a formula in parentheses (the columns' texts in `texts`).
std::string sum_text(const Fit& f, const std::vector<std::string>& texts) {
  double largest = 0;
  for (double c : f.coefficients) largest = std::max(largest, std::abs(c));
  std::string sum;
  for (std::size_t j = 0; j < f.set.size(); ++j) {
    const double c = f.coefficients[j];
    if (f.set[j] == 0) {
      if (std::abs(c) > 1e-13 * largest) sum += (sum.empty() ? "" : " + ") + number(c);
      continue;
    }
    sum += (sum.empty() ? "" : " + ") + ("(" + number(c) + ") * " + texts[f.set[j]]);
  }
  return "(" + (sum.empty() ? std::string("0") : sum) + ")";
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
  std::vector<std::size_t> unsure;  // the inputs whose exponents are farthest from integers
  for (std::size_t k = 0; k < n; ++k) {
    halves[k] = positive ? std::round(2 * b[k + 1]) / 2 : std::round(b[k + 1]);
    wholes[k] = std::round(b[k + 1]);
    if (std::abs(b[k + 1] - wholes[k]) > kUnsureExponent) unsure.push_back(k);
  }
  std::stable_sort(unsure.begin(), unsure.end(), [&](std::size_t i, std::size_t j) {
    return std::abs(b[i + 1] - wholes[i]) > std::abs(b[j + 1] - wholes[j]);
  });
  if (unsure.size() > kUnsureInputs) unsure.resize(kUnsureInputs);
  std::vector<Powers> quotients = {Powers(n, 0.0)};
  // A quotient with an exponent beyond kMostQuotientPower is no physical power law (a steep
  // function over a narrow range fits one) and would not print as `x^k`.
  const auto add = [&](const Powers& m) {
    const bool modest =
        std::all_of(m.begin(), m.end(), [](double e) { return std::abs(e) <= kMostQuotientPower; });
    if (modest && std::find(quotients.begin(), quotients.end(), m) == quotients.end())
      quotients.push_back(m);
  };
  add(halves);
  add(wholes);
  // Where a part of y that is no power product tilts an exponent (w^4 / (w^2 - w0^2)^2 over
  // w0 > w fits w^4.7 w0^-4.8), both integers either side.
  for (std::size_t mask = 0; mask < (std::size_t{1} << unsure.size()); ++mask) {
    Powers m = wholes;
    for (std::size_t u = 0; u < unsure.size(); ++u)
      m[unsure[u]] = (mask >> u & 1) ? std::ceil(b[unsure[u] + 1]) : std::floor(b[unsure[u] + 1]);
    add(m);
  }

  std::optional<Fit> best;
  std::string best_text;
  // Keeps f, which writes y as `text`, when it has fewer terms than the best so far.
  const auto consider = [&](std::optional<Fit> f, const std::string& text) {
    if (!f || (best && f->set.size() >= best->set.size())) return;
    best = std::move(f);
    best_text = text;
  };
  const std::vector<Powers> powers = monomials(n);
  std::vector<std::vector<double>> values(powers.size(), std::vector<double>(rows));
  std::vector<std::string> texts;
  for (std::size_t c = 0; c < powers.size(); ++c) {
    for (std::size_t r = 0; r < rows; ++r) values[c][r] = power_product(s.inputs, powers[c], r);
    texts.push_back(powers_text(powers[c]));
  }
  std::vector<const std::vector<double>*> all;
  for (const std::vector<double>& v : values) all.push_back(&v);

  std::vector<double> q(rows);
  for (const Powers& m : quotients) {
    for (std::size_t r = 0; r < rows; ++r) q[r] = s.target[r] / power_product(s.inputs, m, r);
    for (double p : kPowers) {
      // Even and half powers read |q|, so q must keep one sign; odd ones keep it.
      const bool odd = p == 1 || p == -1;
      const double sign = odd || q[0] > 0 ? 1 : -1;
      if (!odd && !std::all_of(q.begin(), q.end(), [&](double v) { return v * sign > 0; }))
        continue;
      std::vector<double> t(rows);
      for (std::size_t r = 0; r < rows; ++r) t[r] = half_power(sign * q[r], p);
      if (!std::all_of(t.begin(), t.end(), [](double v) { return std::isfinite(v); })) continue;
      Columns d(all, t);
      std::optional<Fit> f = sparse_exact_fit(d, t);
      if (!f) continue;
      // y = sign M g(t), g undoing the power.
      const std::string tq = sum_text(*f, texts);
      std::string text;
      if (p == 1)
        text = tq;
      else if (p == -1)
        text = "1 / " + tq;
      else if (p == 2)
        text = "sqrt" + tq;
      else if (p == -2)
        text = "rsqrt" + tq;
      else if (p == 0.5)
        text = tq + "^2";
      else
        text = "1 / " + tq + "^2";
      if (!odd) text = number(sign) + " * " + text;
      consider(std::move(f), "(" + powers_text(m) + ") * (" + text + ")");
    }
  }
  // The logarithm: log2 |y| = sum e_k log2 |x_k| + c0 + sum a_k m_k, so y = sign exp2(...):
  // exp(-(theta / sigma)^2 / 2) / sigma, whose M no rounding of the fit finds.
  const double sign = s.target[0] > 0 ? 1 : -1;
  if (std::all_of(s.target.begin(), s.target.end(), [&](double v) { return v * sign > 0; })) {
    std::vector<double> t(rows);
    for (std::size_t r = 0; r < rows; ++r) t[r] = std::log2(sign * s.target[r]);
    std::vector<std::vector<double>> logs2(n, std::vector<double>(rows));
    std::vector<const std::vector<double>*> with_logs = all;
    std::vector<std::string> with_logs_texts = texts;
    for (std::size_t k = 0; k < n; ++k) {
      for (std::size_t r = 0; r < rows; ++r) logs2[k][r] = std::log2(std::abs(s.inputs[k][r]));
      with_logs.push_back(&logs2[k]);
      with_logs_texts.push_back("log2(abs(x" + std::to_string(k) + "))");
    }
    Columns d(with_logs, t);
    std::optional<Fit> f = sparse_exact_fit(d, t);
    if (f) {
      const std::string tq = sum_text(*f, with_logs_texts);
      consider(std::move(f), number(sign) + " * exp2" + tq);
    }
  }
  if (!best) return std::nullopt;
  return best_text;
}

}  // namespace shaderfit::search_detail
