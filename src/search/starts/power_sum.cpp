#include "search/starts/power_sum.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

#include "search/starts/row_sample.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/fit/linear.hpp"

namespace shaderfit::search_detail {

namespace {

constexpr std::size_t kBeam = 32;
constexpr double kSift = 1e-6;  // 1 - R^2 by the normal equations worth a refit on the rows
// A transform t whose spread about its mean is below this share of its square is constant: the
// rounding of float64 data leaves about 1e-32, a CSV of 7 digits 1e-14.
constexpr double kConstantSpread = 1e-20;
// The logarithm's columns include power products of three inputs while the columns stay this
// few (6 inputs: 1,545), and one power product of any inputs is tried alone, among this many.
constexpr std::size_t kLogColumns = 1600;
constexpr std::size_t kWideMonomials = 20000;
// The logarithm takes a term more than a sum: log2 sigma beside the three of
// ((theta - theta1) / sigma)^2.
constexpr std::size_t kLogTerms = kPowerSumTerms + 1;
// The split of M and the sum by the log fit's exponents: at most 5 inputs in the sum, products of
// up to 4 of them (2,101 columns).
constexpr std::size_t kSplitInputs = 5;
constexpr std::size_t kSplitPresent = 4;
constexpr double kFactorExponents[] = {0.04, 0.1};
// rational_sum tries (4 n + 1)^2 pairs of scales: 289 fits of about 30 columns for 4 inputs.
constexpr std::size_t kRationalInputs = 4;
// exponential_rational tries 3^n - 1 power products (242 for 5 inputs), refines an a where the
// grid leaves a mean square relative error below kExponentialSift, and keeps a formula whose
// relative error on every row is at most kExponentialExact.
constexpr std::size_t kExponentialInputs = 5;
constexpr double kExponentialSift = 1e-3;
constexpr double kExponentialExact = 1e-9;
// What any formula found must meet on every row (holds_on_rows).
constexpr double kRowExact = 1e-9;
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

// The power products of n inputs with at most `most` of them present, each with an exponent
// from kExponents, in order of how many are present ([0] the constant).
std::vector<Powers> monomials(std::size_t n, std::size_t most) {
  std::vector<Powers> out = {Powers(n, 0.0)};
  std::size_t from = 0;
  for (std::size_t present = 1; present <= std::min(most, n); ++present) {
    const std::size_t to = out.size();
    for (std::size_t i = from; i < to; ++i) {
      // Extend by an input after the last present one, so each product is made once.
      std::size_t first = 0;
      for (std::size_t k = 0; k < n; ++k)
        if (out[i][k] != 0) first = k + 1;
      for (std::size_t k = first; k < n; ++k)
        for (int a : kExponents) {
          Powers next = out[i];
          next[k] = a;
          out.push_back(std::move(next));
        }
    }
    from = to;
  }
  return out;
}

// How many power products monomials(n, most) makes.
std::size_t monomial_count(std::size_t n, std::size_t most) {
  std::size_t count = 0, choose = 1, per = 1;  // C(n, j), 4^j
  for (std::size_t j = 0; j <= std::min(most, n); ++j) {
    count += choose * per;
    choose = choose * (n - j) / (j + 1);
    per *= std::size(kExponents);
  }
  return count;
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

using Subset = std::array<std::size_t, kLogTerms + 2>;  // one spare: a level's new column

// The Cholesky factor of the normal equations of the scaled columns `set` (the constant, index
// 0, always among them) and the projection z of t on them: t's residual sum of squares is
// t.t - z.z, and a column more extends both by one row.
struct Factor {
  std::array<std::array<double, kLogTerms + 2>, kLogTerms + 2> l{};
  std::array<double, kLogTerms + 2> z{};
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

// The fewest columns, at most `terms` (no more than kLogTerms), that explain t exactly
// (kPowerSumExact), by a beam search.
std::optional<Fit> sparse_exact_fit(Columns& d, const std::vector<double>& t, std::size_t terms) {
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
  // t constant to float64 rounding: y is the transform's power product alone (1 / (4 pi eps c^2)
  // 2 I / r), a sum of no terms, which 1 - R^2 cannot judge.
  if (spread <= kConstantSpread * tt && tt > 0) return Fit{{0}, {mean}, 0};
  if (!(spread > 0)) return std::nullopt;
  // A subset is the constant and up to `terms` columns, packed 12 bits each in ascending order
  // into one key.
  static_assert(kLogTerms * 12 <= 64);
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
  for (std::size_t level = 1; level <= terms; ++level) {
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

std::string log_text(std::size_t k) { return "log2(abs(x" + std::to_string(k) + "))"; }

// t by every column at once, refitted on the rows; where that is exact (kPowerSumExact), refitted
// with the first `kept` columns and those others that have a part in it, or nullopt.
std::optional<Fit> exact_full_fit(const std::vector<const std::vector<double>*>& columns,
                                  const std::vector<double>& t, std::size_t kept) {
  Columns d(columns, t);
  std::vector<std::size_t> set(columns.size());
  for (std::size_t c = 0; c < set.size(); ++c) set[c] = c;
  Fit f = refit(d, t, set);
  if (f.unexplained > kPowerSumExact) return std::nullopt;
  // A column has a part when its share of t is above rounding (the QR leaves about 1e-13 on
  // columns that have none).
  double t_norm = 0;
  for (double v : t) t_norm += v * v;
  t_norm = std::sqrt(t_norm);
  std::vector<std::size_t> needed;
  for (std::size_t c = 0; c < set.size(); ++c) {
    double norm = 0;
    for (double v : *columns[c]) norm += v * v;
    if (c < kept || std::abs(f.coefficients[c]) * std::sqrt(norm) > 1e-9 * t_norm)
      needed.push_back(c);
  }
  f = refit(d, t, needed);
  if (f.unexplained > kPowerSumExact) return std::nullopt;
  return f;
}

// The power products D q(x), q a polynomial of degree 2 in the inputs (its constant included),
// D = `scale`; each once, and the constant 1 left out when `with_one` is false.
std::vector<Powers> scaled_quadratic(const Powers& scale, bool with_one) {
  const std::size_t n = scale.size();
  std::vector<Powers> out;
  for (std::size_t i = 0; i <= n; ++i)
    for (std::size_t j = i; j <= n; ++j) {
      Powers m = scale;
      if (i < n) m[i] += 1;
      if (j < n) m[j] += 1;
      const bool one = std::all_of(m.begin(), m.end(), [](double e) { return e == 0; });
      if ((with_one || !one) && std::find(out.begin(), out.end(), m) == out.end())
        out.push_back(std::move(m));
    }
  return out;
}

// 1 and every input to a power from kExponents: the scales D of scaled_quadratic.
std::vector<Powers> single_powers(std::size_t n) {
  std::vector<Powers> out = {Powers(n, 0.0)};
  for (std::size_t k = 0; k < n; ++k)
    for (int a : kExponents) {
      out.emplace_back(n, 0.0);
      out.back()[k] = a;
    }
  return out;
}

std::vector<double> product_column(const std::vector<std::vector<double>>& inputs,
                                   const Powers& m) {
  std::vector<double> v(inputs.empty() ? 0 : inputs[0].size());
  for (std::size_t r = 0; r < v.size(); ++r) v[r] = power_product(inputs, m, r);
  return v;
}

// log2 |y| = c0 + sum e_k log2 |x_k| + sum a_j m_j over the power products `products`, by
// exact_full_fit (the constant always kept). The fit and its columns' texts ([0] the constant,
// then the logarithms, then the products), or nullopt.
std::optional<std::pair<Fit, std::vector<std::string>>> exact_logarithm(
    const std::vector<std::vector<double>>& inputs, const std::vector<std::vector<double>>& logs2,
    const std::vector<double>& t, const std::vector<Powers>& products) {
  const std::size_t n = inputs.size(), rows = t.size();
  std::vector<std::vector<double>> values = {std::vector<double>(rows, 1.0)};
  for (const Powers& m : products) values.push_back(product_column(inputs, m));
  std::vector<std::string> texts = {""};
  std::vector<const std::vector<double>*> columns = {&values[0]};
  for (std::size_t k = 0; k < n; ++k) {
    columns.push_back(&logs2[k]);
    texts.push_back(log_text(k));
  }
  for (std::size_t j = 0; j < products.size(); ++j) {
    columns.push_back(&values[j + 1]);
    texts.push_back(powers_text(products[j]));
  }
  std::optional<Fit> f = exact_full_fit(columns, t, 1);
  if (!f) return std::nullopt;
  return std::pair{std::move(*f), std::move(texts)};
}

// An orthonormal basis of the constant and the logarithms of the inputs (modified Gram-Schmidt;
// a logarithm that depends on the others is left out), for residuals after a fit on them.
class LogBasis {
 public:
  explicit LogBasis(const std::vector<std::vector<double>>& logs) {
    const std::size_t rows = logs.empty() ? 0 : logs[0].size();
    for (std::size_t c = 0; c <= logs.size(); ++c) {
      std::vector<double> v = c == 0 ? std::vector<double>(rows, 1.0) : logs[c - 1];
      double before = 0;
      for (double x : v) before += x * x;
      const double norm = std::sqrt(outside(v));
      if (!(norm > 1e-9 * std::sqrt(before))) continue;
      for (double& x : v) x /= norm;
      basis_.push_back(std::move(v));
    }
  }
  // v less its projection on the basis; returns what is left's sum of squares.
  double outside(std::vector<double>& v) const {
    for (const std::vector<double>& q : basis_) {
      double d = 0;
      for (std::size_t r = 0; r < v.size(); ++r) d += q[r] * v[r];
      for (std::size_t r = 0; r < v.size(); ++r) v[r] -= d * q[r];
    }
    double left = 0;
    for (double x : v) left += x * x;
    return left;
  }

 private:
  std::vector<std::vector<double>> basis_;
};

// The logarithm with one power product of any inputs: log2 |y| = c0 + sum e_k log2 |x_k| + a m,
// where m has as many inputs present as kWideMonomials allows (n0 exp(-m g x / (kb T)) has five;
// the beam's columns have at most three). Every m is judged by how much of t's residual after the
// logarithms it explains; the best is refitted on the rows with the logarithms, and those with no
// part in it are dropped. The fit and its columns' texts ([0] the constant), or nullopt.
std::optional<std::pair<Fit, std::vector<std::string>>> wide_logarithm(
    const std::vector<std::vector<double>>& inputs, const std::vector<std::vector<double>>& logs2,
    const std::vector<double>& t) {
  const std::size_t n = inputs.size(), rows = t.size();
  std::size_t most = 0;
  while (most < n && monomial_count(n, most + 1) <= kWideMonomials) ++most;
  const LogBasis basis(logs2);
  const auto project_out = [&](std::vector<double>& v) { basis.outside(v); };
  const auto dot = [&](const std::vector<double>& a, const std::vector<double>& b) {
    double d = 0;
    for (std::size_t r = 0; r < rows; ++r) d += a[r] * b[r];
    return d;
  };
  double mean = 0;
  for (double v : t) mean += v;
  mean /= static_cast<double>(rows);
  double spread = 0;
  for (double v : t) spread += (v - mean) * (v - mean);
  std::vector<double> residual = t;
  project_out(residual);
  const double rr = dot(residual, residual);
  if (!(spread > 0) || rr <= kPowerSumExact * spread) return std::nullopt;

  // x_k^a for a in kExponents.
  std::vector<std::array<std::vector<double>, std::size(kExponents)>> raised(n);
  for (std::size_t k = 0; k < n; ++k)
    for (std::size_t a = 0; a < std::size(kExponents); ++a) {
      raised[k][a].resize(rows);
      for (std::size_t r = 0; r < rows; ++r)
        raised[k][a][r] = half_power(inputs[k][r], kExponents[a]);
    }
  double best_left = rr;
  Powers best, current(n, 0.0);
  std::vector<std::vector<double>> products(most + 1, std::vector<double>(rows, 1.0));
  std::vector<double> m(rows);
  // Extends the product of `present` inputs by each input from `first` on.
  const auto visit = [&](const auto& self, std::size_t first, std::size_t present) -> void {
    for (std::size_t k = first; k < n; ++k)
      for (std::size_t a = 0; a < std::size(kExponents); ++a) {
        std::vector<double>& p = products[present + 1];
        for (std::size_t r = 0; r < rows; ++r) p[r] = products[present][r] * raised[k][a][r];
        current[k] = kExponents[a];
        m = p;
        const double norm = std::sqrt(dot(m, m));
        project_out(m);
        const double mm = dot(m, m);
        if (std::isfinite(mm) && mm > 1e-18 * norm * norm) {
          const double rm = dot(residual, m);
          const double left = rr - rm * rm / mm;
          if (left < best_left) {
            best_left = left;
            best = current;
          }
        }
        if (present + 1 < most) self(self, k + 1, present + 1);
        current[k] = 0;
      }
  };
  visit(visit, 0, 0);
  if (best.empty() || best_left > kSift * spread) return std::nullopt;

  return exact_logarithm(inputs, logs2, t, {best});
}

// log2 |y| = c0 + sum e_k log2 |x_k| + D q(x), q a polynomial of degree 2 in the inputs and D
// 1 or one input to a power from kExponents, every coefficient fitted at once: a Gaussian
// exp(-((theta - theta1) / sigma)^2 / 2) / sigma has four terms, whose parts the beam cannot
// rank (each alone explains little). The fit of the fewest terms, or nullopt.
std::optional<std::pair<Fit, std::vector<std::string>>> quadratic_logarithm(
    const std::vector<std::vector<double>>& inputs, const std::vector<std::vector<double>>& logs2,
    const std::vector<double>& t) {
  std::optional<std::pair<Fit, std::vector<std::string>>> best;
  for (const Powers& scale : single_powers(inputs.size())) {
    auto f = exact_logarithm(inputs, logs2, t, scaled_quadratic(scale, false));
    if (f && (!best || f->first.set.size() < best->first.set.size())) best = std::move(f);
  }
  return best;
}

// y = N / (1 + E), N = D1 q1(x) and E = D2 q2(x) as in scaled_quadratic (E without the constant),
// fitted at once as the linear y = N - y E: (u + v) / (1 + u v / c^2), where the beam, choosing
// the columns one by one, loses the denominator. For kRationalInputs inputs at most (the pairs of
// scales grow as n^2). The formula of the fewest terms, or "".
std::string rational_sum(const std::vector<std::vector<double>>& inputs,
                         const std::vector<double>& y) {
  const std::size_t n = inputs.size(), rows = y.size();
  if (n > kRationalInputs) return "";
  const std::vector<Powers> scales = single_powers(n);
  std::size_t fewest = std::numeric_limits<std::size_t>::max();
  std::string out;
  for (const Powers& top : scales) {
    const std::vector<Powers> numerator = scaled_quadratic(top, true);
    std::vector<std::vector<double>> top_values;
    for (const Powers& m : numerator) top_values.push_back(product_column(inputs, m));
    for (const Powers& bottom : scales) {
      const std::vector<Powers> denominator = scaled_quadratic(bottom, false);
      std::vector<std::vector<double>> values = top_values;
      for (const Powers& m : denominator) {
        values.push_back(product_column(inputs, m));
        for (std::size_t r = 0; r < rows; ++r) values.back()[r] *= -y[r];
      }
      std::vector<const std::vector<double>*> columns;
      for (const std::vector<double>& v : values) columns.push_back(&v);
      const std::optional<Fit> f = exact_full_fit(columns, y, 0);
      if (!f || f->set.size() >= fewest) continue;
      std::string num, den = "1";
      for (std::size_t j = 0; j < f->set.size(); ++j) {
        const std::size_t c = f->set[j];
        const bool up = c < numerator.size();
        const std::string term = "(" + number(f->coefficients[j]) + ") * (" +
                                 powers_text(up ? numerator[c] : denominator[c - numerator.size()]) +
                                 ")";
        std::string& side = up ? num : den;
        side += (side.empty() ? "" : " + ") + term;
      }
      if (num.empty()) continue;
      fewest = f->set.size();
      out = "(" + num + ") / (" + den + ")";
    }
  }
  return out;
}

// y = C M0 / h(E), E = exp2(a m), m a power product with exponents in {-1, 1} and M0 one with
// exponents from the log fit, for h(E) in E - 1 (Planck, Bose-Einstein), E + 1 (Fermi-Dirac),
// E + 1 / E (1 / cosh) and (E + 1) / (E - 1) (tanh, a halved): then y h(E) is the power product
// C M0. For each m, a is found by a grid over a m's median and golden sections in log |a|, each
// a judged by how far log |y h(E)| is from linear in the log |x_k|. For kExponentialInputs
// inputs at most (the m are 3^n - 1). The formula, or "".
std::string exponential_rational(const std::vector<std::vector<double>>& inputs,
                                 const std::vector<double>& y) {
  const std::size_t n = inputs.size(), rows = y.size();
  if (n > kExponentialInputs) return "";
  std::vector<std::vector<double>> logs(n, std::vector<double>(rows));
  for (std::size_t k = 0; k < n; ++k)
    for (std::size_t r = 0; r < rows; ++r) logs[k][r] = std::log(std::abs(inputs[k][r]));
  const LogBasis basis(logs);
  const auto outside = [&](std::vector<double>& v) { return basis.outside(v); };
  constexpr int kinds[] = {0, 1, 2, 3};
  const auto h = [](int kind, double e) {
    switch (kind) {
      case 0: return e - 1;
      case 1: return e + 1;
      case 2: return e + 1 / e;
      default: return (e + 1) / (e - 1);
    }
  };
  std::vector<double> m(rows), z(rows);
  // The mean square of log |y h(E)| outside the logs (the relative error of y by C M0 / h(E),
  // squared), for E = exp2(a m) on each row in `powers`; kNoFit where y h(E) changes sign. Not
  // 1 - R^2: y h(E) is constant where C M0 is.
  constexpr double kNoFit = 1e300;
  const auto unexplained_of = [&](int kind, const std::vector<double>& powers) {
    bool positive = true, negative = true;
    for (std::size_t r = 0; r < rows; ++r) {
      const double v = y[r] * h(kind, powers[r]);
      positive = positive && v > 0;
      negative = negative && v < 0;
      z[r] = std::log(std::abs(v));
    }
    if (!(positive || negative)) return kNoFit;
    const double left = outside(z);
    return std::isfinite(left) ? left / static_cast<double>(rows) : kNoFit;
  };
  std::vector<double> at(rows);
  const auto unexplained = [&](int kind, double a) {
    for (std::size_t r = 0; r < rows; ++r) at[r] = std::exp2(a * m[r]);
    return unexplained_of(kind, at);
  };
  Powers e(n, 0.0);
  std::string out;
  // Each m with exponents in {-1, 0, 1}, counted in base 3.
  std::size_t count = 1;
  for (std::size_t k = 0; k < n; ++k) count *= 3;
  for (std::size_t code = 1; code < count && out.empty(); ++code) {
    std::size_t c = code;
    for (std::size_t k = 0; k < n; ++k, c /= 3) e[k] = static_cast<double>(c % 3) - 1;
    m = product_column(inputs, e);
    std::vector<double> sorted = m;
    std::nth_element(sorted.begin(), sorted.begin() + rows / 2, sorted.end());
    const double median = std::abs(sorted[rows / 2]);
    if (!(median > 0) || !std::isfinite(median)) continue;
    // log2 (a median) from -6 to 6 by 1/2, either sign of a, for every h at once.
    std::array<double, 4> best_a{}, best{kNoFit, kNoFit, kNoFit, kNoFit};
    std::vector<double> powers(rows);
    for (const double sign : {1.0, -1.0})
      for (int g = -12; g <= 12; ++g) {
        const double a = sign * std::exp2(g / 2.0) / median;
        for (std::size_t r = 0; r < rows; ++r) powers[r] = std::exp2(a * m[r]);
        for (const int kind : kinds) {
          const double u = unexplained_of(kind, powers);
          if (u < best[kind]) {
            best[kind] = u;
            best_a[kind] = a;
          }
        }
      }
    for (const int kind : kinds) {
      if (!(best[kind] < kExponentialSift)) continue;
      // Golden sections in log |a| within a step either side.
      const double sign = best_a[kind] < 0 ? -1 : 1;
      double lo = std::log2(std::abs(best_a[kind])) - 0.5, hi = lo + 1;
      const double phi = 0.6180339887498949;
      for (int i = 0; i < 100 && hi - lo > 1e-15; ++i) {
        const double x1 = hi - phi * (hi - lo), x2 = lo + phi * (hi - lo);
        if (unexplained(kind, sign * std::exp2(x1)) < unexplained(kind, sign * std::exp2(x2)))
          hi = x2;
        else
          lo = x1;
      }
      const double a = sign * std::exp2((lo + hi) / 2);
      if (!(unexplained(kind, a) <= kExponentialExact * kExponentialExact)) continue;
      // C M0: the log fit's exponents rounded to integers, C refitted; exact or nothing.
      const std::vector<double> ones(rows, 1.0);
      std::vector<const double*> columns = {ones.data()};
      for (const auto& l : logs) columns.push_back(l.data());
      std::vector<double> target(rows);
      double zs = 0;
      for (std::size_t r = 0; r < rows; ++r) {
        const double v = y[r] * h(kind, std::exp2(a * m[r]));
        target[r] = std::log(std::abs(v));
        zs = v;
      }
      const std::vector<double> fit = solve_least_squares(columns, target);
      Powers m0(n);
      for (std::size_t k = 0; k < n; ++k) m0[k] = std::round(fit[k + 1]);
      double log_c = 0, worst = 0;
      for (std::size_t r = 0; r < rows; ++r) log_c += target[r] - std::log(power_product(inputs, m0, r));
      log_c /= static_cast<double>(rows);
      const double scale = (zs < 0 ? -1 : 1) * std::exp(log_c);
      for (std::size_t r = 0; r < rows; ++r) {
        const double g = scale * power_product(inputs, m0, r) / h(kind, std::exp2(a * m[r]));
        worst = std::max(worst, std::abs(g / y[r] - 1));
      }
      if (!(worst <= kExponentialExact)) continue;
      const std::string ex = "exp2(" + number(a) + " * " + powers_text(e) + ")";
      const std::string top = number(scale) + " * (" + powers_text(m0) + ")";
      switch (kind) {
        case 0: out = top + " / (" + ex + " - 1)"; break;
        case 1: out = top + " / (" + ex + " + 1)"; break;
        case 2: out = top + " / (" + ex + " + 1 / " + ex + ")"; break;
        default: out = top + " * (" + ex + " - 1) / (" + ex + " + 1)"; break;
      }
      break;
    }
  }
  return out;
}

// Whether the formula `text` (inputs x0, x1, ...) gives y on every row of s to within
// kRowExact of |y| + rms(y): 1 - R^2 <= 1e-12 in t does not say so where y spans decades (the
// series 1 / x - 1 + x / 3 under a square root passes for 1 / (exp(x / (2 pi)) - 1) on
// [0.08, 9], its error far above rounding where y is small).
bool holds_on_rows(const std::string& text, const SearchProblem& s) {
  ParseOptions po;
  for (std::size_t k = 0; k < s.inputs.size(); ++k) po.variables.push_back("x" + std::to_string(k));
  Expression e;
  try {
    e = parse_formula(text, po);
  } catch (const Error&) {
    return false;
  }
  double square = 0;
  for (double v : s.target) square += v * v;
  const double rms = std::sqrt(square / static_cast<double>(s.target.size()));
  std::vector<double> row(s.inputs.size());
  for (std::size_t r = 0; r < s.target.size(); ++r) {
    for (std::size_t k = 0; k < row.size(); ++k) row[k] = s.inputs[k][r];
    const double g = evaluate_scalar(e, row);
    if (!(std::abs(g - s.target[r]) <= kRowExact * (std::abs(s.target[r]) + rms))) return false;
  }
  return true;
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
    if (!f || (best && f->set.size() >= best->set.size()) || !holds_on_rows(text, s)) return;
    best = std::move(f);
    best_text = text;
  };
  // The logarithm's columns are the sum's, and the products of three inputs where they are few.
  const std::size_t log_most = monomial_count(n, 3) + n <= kLogColumns ? 3 : 2;
  const std::vector<Powers> powers = monomials(n, log_most);
  const std::size_t sum_columns = monomial_count(n, 2);
  std::vector<std::vector<double>> values;
  std::vector<std::string> texts;
  for (const Powers& m : powers) {
    values.push_back(product_column(s.inputs, m));
    texts.push_back(powers_text(m));
  }
  std::vector<const std::vector<double>*> all;
  for (std::size_t c = 0; c < sum_columns; ++c) all.push_back(&values[c]);

  // Tries y = M g(t) for each power p, t a sum of the columns `cols` (their texts `col_texts`).
  std::vector<double> q(rows);
  const auto try_quotient = [&](const Powers& m, const std::vector<const std::vector<double>*>& cols,
                                const std::vector<std::string>& col_texts) {
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
      Columns d(cols, t);
      std::optional<Fit> f = sparse_exact_fit(d, t, kPowerSumTerms);
      if (!f) continue;
      // y = sign M g(t), g undoing the power.
      const std::string tq = sum_text(*f, col_texts);
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
  };
  for (const Powers& m : quotients) try_quotient(m, all, texts);

  // An input whose exponent in the log fit is near an integer enters y as a factor of M, one far
  // from integers enters the sum: M of the first kind alone, t a sum of products of up to
  // kSplitPresent inputs of the second (mom / (kb T) (H + alpha M / (epsilon c^2)) has one of
  // four), where those are 3 to kSplitInputs. "Near" at each of kFactorExponents: the fit on 256
  // rows moves a factor's exponent by up to about 0.02, and an input of the sum may sit 0.1 from
  // an integer.
  std::vector<std::size_t> tried_inner;
  for (const double near : kFactorExponents) {
    if (best) break;
    Powers outer(n, 0.0);
    std::vector<std::size_t> inner;
    for (std::size_t k = 0; k < n; ++k) {
      if (std::abs(b[k + 1] - wholes[k]) <= near)
        outer[k] = wholes[k];
      else
        inner.push_back(k);
    }
    if (inner.size() < 3 || inner.size() > kSplitInputs || inner == tried_inner) continue;
    tried_inner = inner;
    std::vector<std::vector<double>> split_values;
    std::vector<std::string> split_texts;
    for (const Powers& few : monomials(inner.size(), kSplitPresent)) {
      Powers m(n, 0.0);
      for (std::size_t i = 0; i < inner.size(); ++i) m[inner[i]] = few[i];
      split_values.push_back(product_column(s.inputs, m));
      split_texts.push_back(powers_text(m));
    }
    std::vector<const std::vector<double>*> split;
    for (const std::vector<double>& v : split_values) split.push_back(&v);
    try_quotient(outer, split, split_texts);
  }
  // The logarithm: log2 |y| = sum e_k log2 |x_k| + c0 + sum a_k m_k, so y = sign exp2(...):
  // exp(-(theta / sigma)^2 / 2) / sigma, whose M no rounding of the fit finds.
  const double sign = s.target[0] > 0 ? 1 : -1;
  if (std::all_of(s.target.begin(), s.target.end(), [&](double v) { return v * sign > 0; })) {
    std::vector<double> t(rows);
    for (std::size_t r = 0; r < rows; ++r) t[r] = std::log2(sign * s.target[r]);
    std::vector<std::vector<double>> logs2(n, std::vector<double>(rows));
    std::vector<const std::vector<double>*> with_logs;
    for (const std::vector<double>& v : values) with_logs.push_back(&v);
    std::vector<std::string> with_logs_texts = texts;
    for (std::size_t k = 0; k < n; ++k) {
      for (std::size_t r = 0; r < rows; ++r) logs2[k][r] = std::log2(std::abs(s.inputs[k][r]));
      with_logs.push_back(&logs2[k]);
      with_logs_texts.push_back(log_text(k));
    }
    Columns d(with_logs, t);
    std::optional<Fit> f = sparse_exact_fit(d, t, kLogTerms);
    if (f) {
      const std::string tq = sum_text(*f, with_logs_texts);
      consider(std::move(f), number(sign) + " * exp2" + tq);
    } else if (!best) {
      auto w = quadratic_logarithm(s.inputs, logs2, t);
      if (!w) w = wide_logarithm(s.inputs, logs2, t);
      if (w) {
        const std::string tq = sum_text(w->first, w->second);
        consider(std::move(w->first), number(sign) + " * exp2" + tq);
      }
    }
  }
  if (!best) {
    std::string other = rational_sum(s.inputs, s.target);
    if (other.empty() || !holds_on_rows(other, s)) other = exponential_rational(s.inputs, s.target);
    if (!other.empty() && holds_on_rows(other, s)) return other;
    return std::nullopt;
  }
  return best_text;
}

}  // namespace shaderfit::search_detail
