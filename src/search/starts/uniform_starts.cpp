#include "search/starts/uniform_starts.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>

#include "search/evolution/constant_fit.hpp"
#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/expr/print.hpp"
#include "shaderfit/fit/linear.hpp"

namespace shaderfit::search_detail {

namespace {

std::string number(double v) { return fmt::format("{:.17g}", v); }

// A column over the rows read, and its text over x0, x1, ...
struct Column {
  std::string text;
  std::vector<double> values;
};

bool finite(const std::vector<double>& v) {
  return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
}

// The per-pixel bases of one varying input: its value in row r is x[r].
std::vector<Column> bases_of(const std::string& x, const std::vector<double>& v) {
  struct Shape {
    const char* text;  // {} is the input
    std::function<double(double)> f;
  };
  const Shape shapes[] = {
      {"{}", [](double a) { return a; }},
      {"{}^2", [](double a) { return a * a; }},
      {"1/{}", [](double a) { return 1 / a; }},
      {"1/{}^2", [](double a) { return 1 / (a * a); }},
      {"sqrt({})", [](double a) { return std::sqrt(a); }},
      {"rsqrt({})", [](double a) { return 1 / std::sqrt(a); }},
      {"log2({})", [](double a) { return std::log2(a); }},
      // For a cosine: tan and sin (the slope of a microfacet model's a = cot / alpha).
      {"{0}*rsqrt(1 - {0}^2)", [](double a) { return a / std::sqrt(1 - a * a); }},
      {"sqrt(1 - {0}^2)", [](double a) { return std::sqrt(1 - a * a); }},
  };
  std::vector<Column> out;
  for (const Shape& s : shapes) {
    Column c{fmt::format(fmt::runtime(s.text), x), {}};
    if (c.text.find(' ') != std::string::npos) c.text = "(" + c.text + ")";
    for (double a : v) c.values.push_back(s.f(a));
    const bool varies =
        std::any_of(c.values.begin(), c.values.end(), [&](double a) { return a != c.values[0]; });
    if (finite(c.values) && varies) out.push_back(std::move(c));
  }
  return out;
}

}  // namespace

std::vector<std::string> uniform_starts(const SearchProblem& problem, const SearchOptions& options,
                                        std::span<const Expression> terminals,
                                        const std::function<bool()>& over) {
  const auto stop = [&] { return over && over(); };
  const std::size_t inputs = problem.inputs.size(), all_rows = problem.target.size();
  if (options.uniform.empty() || all_rows == 0) return {};
  std::vector<std::string> names;
  for (std::size_t k = 0; k < inputs; ++k) names.push_back("x" + std::to_string(k));
  auto is_uniform = [&](std::size_t k) {
    return std::find(options.uniform.begin(), options.uniform.end(), problem.input_names[k]) !=
           options.uniform.end();
  };

  // The rows read, evenly spread.
  const std::size_t n = std::min(all_rows, kUniformStartRows);
  std::vector<std::size_t> rows;
  for (std::size_t k = 0; k < n; ++k) rows.push_back(n == 1 ? 0 : k * (all_rows - 1) / (n - 1));
  std::vector<double> y, w0;
  for (std::size_t r : rows) {
    y.push_back(problem.target[r]);
    w0.push_back(problem.weights.empty() ? 1.0 : problem.weights[r]);
  }
  auto column_of = [&](std::size_t k) {
    std::vector<double> v;
    for (std::size_t r : rows) v.push_back(problem.inputs[k][r]);
    return v;
  };

  // The per-pixel bases, and the coefficient functions (the uniform inputs, the terminals).
  std::vector<Column> bases, coefficients;
  for (std::size_t k = 0; k < inputs; ++k) {
    if (is_uniform(k)) {
      coefficients.push_back({names[k], column_of(k)});
    } else {
      for (Column& c : bases_of(names[k], column_of(k))) bases.push_back(std::move(c));
    }
  }
  if (bases.empty()) return {};
  for (const Expression& t : terminals) {
    Expression e = t;
    e.variables = names;
    Column c{to_infix(e), std::vector<double>(n)};
    std::vector<std::vector<double>> cols;
    std::vector<const double*> pointers;
    for (std::size_t k = 0; k < inputs; ++k) cols.push_back(column_of(k));
    for (const auto& col : cols) pointers.push_back(col.data());
    evaluate(t, pointers, c.values, {.threads = 1});
    if (finite(c.values)) coefficients.push_back(std::move(c));
  }

  // Fits in two domains: y itself, and log2 y for exp2 forms of a positive target.
  const Loss loss = options.loss;
  const bool minimax = fits_minimax(loss);
  const bool positive = std::all_of(y.begin(), y.end(), [](double v) { return v > 0; });
  std::vector<double> log2_y;
  for (double v : y) log2_y.push_back(positive ? std::log2(v) : 0.0);
  // Row weights per domain, in the loss's terms: minimax weights, or the least squares' (rel and
  // log weigh 1/y^2); in log2 y an error d is a relative error d ln 2 there, so the weights of an
  // absolute loss take y's scale.
  std::vector<double> w_lin = minimax ? minimax_weights(loss, y, w0) : w0;
  const bool relative = loss == Loss::Relative || loss == Loss::Log || loss == Loss::MaxRel;
  if (!minimax && relative)
    for (std::size_t r = 0; r < n; ++r) w_lin[r] = y[r] != 0 ? w0[r] / (y[r] * y[r]) : 0;
  std::vector<double> w_log(n);
  for (std::size_t r = 0; r < n; ++r) {
    const double scale = relative ? 1.0 : std::abs(y[r]);
    w_log[r] = w0[r] * (minimax ? scale : scale * scale);
  }

  // Linear: a0 + sum a_k b_k; Exp2: exp2 of that; Rational: (a0 + a1 b + ... a_d b^d) /
  // (1 + e1 b + ... e_d b^d) in one basis, fitted linearised (y = N - y (D - 1)).
  enum class Form { Linear, Exp2, Rational };
  struct Fit {
    std::vector<std::size_t> bases, coefficient_set;
    Form form = Form::Linear;
    int degree = 0;  // Rational
    std::vector<double> c;
    double error = std::numeric_limits<double>::infinity();
  };
  const std::vector<double> ones(n, 1.0);
  // The fit's error in the loss's terms on y (max w |r|, or sum w r^2).
  auto fit = [&](const std::vector<std::size_t>& b, const std::vector<std::size_t>& t, Form form,
                 int degree) {
    Fit f{b, t, form, degree, {}, std::numeric_limits<double>::infinity()};
    // The terms' factors of a basis: 1, then the bases (Linear, Exp2) or the powers of the one
    // basis (Rational: numerator 0 .. d, then denominator 1 .. d times -y).
    std::vector<std::vector<double>> factors;
    factors.push_back(ones);
    if (form != Form::Rational) {
      for (std::size_t k : b) factors.push_back(bases[k].values);
    } else {
      const std::vector<double>& v = bases[b.front()].values;
      for (int p = 1; p <= degree; ++p) {
        std::vector<double> col(n);
        for (std::size_t r = 0; r < n; ++r) col[r] = std::pow(v[r], p);
        factors.push_back(std::move(col));
      }
      for (int p = 1; p <= degree; ++p) {
        std::vector<double> col(n);
        for (std::size_t r = 0; r < n; ++r) col[r] = -y[r] * std::pow(v[r], p);
        factors.push_back(std::move(col));
      }
    }
    std::vector<std::vector<double>> cols;
    for (const std::vector<double>& base : factors) {
      for (int j = -1; j < static_cast<int>(t.size()); ++j) {
        const std::vector<double>& coef =
            j < 0 ? ones : coefficients[t[static_cast<std::size_t>(j)]].values;
        std::vector<double> col(n);
        for (std::size_t r = 0; r < n; ++r) col[r] = base[r] * coef[r];
        cols.push_back(std::move(col));
      }
    }
    if (cols.size() >= n) return f;
    std::vector<const double*> pointers;
    for (const auto& col : cols) pointers.push_back(col.data());
    const bool exp2 = form == Form::Exp2;
    const std::vector<double>& target = exp2 ? log2_y : y;
    const std::vector<double>& w = exp2 ? w_log : w_lin;
    f.c = minimax ? solve_minimax_linear(pointers, target, w, 30)
                  : solve_least_squares(pointers, target, w);
    if (!std::all_of(f.c.begin(), f.c.end(), [](double v) { return std::isfinite(v); })) return f;
    const std::size_t per = t.size() + 1;  // constants per coefficient
    double error = 0;
    for (std::size_t r = 0; r < n; ++r) {
      double g = 0;
      if (form == Form::Rational) {
        // Coefficient block k multiplies b^k (k <= d, numerator) or b^(k - d) (denominator).
        const double v = bases[b.front()].values[r];
        double num = 0, den = 1;
        for (std::size_t j = 0; j < cols.size(); ++j) {
          const std::size_t k = j / per, jj = j % per;
          const double coef = jj == 0 ? 1.0 : coefficients[t[jj - 1]].values[r];
          const int p = static_cast<int>(
              k <= static_cast<std::size_t>(degree) ? k : k - static_cast<std::size_t>(degree));
          const double term = f.c[j] * coef * std::pow(v, p);
          if (k <= static_cast<std::size_t>(degree))
            num += term;
          else
            den += term;
        }
        g = num / den;
      } else {
        for (std::size_t j = 0; j < cols.size(); ++j) g += f.c[j] * cols[j][r];
        if (exp2) g = std::exp2(g);
      }
      const double e = w_lin[r] * std::abs(g - y[r]);
      error = minimax ? std::max(error, e) : error + e * std::abs(g - y[r]);
    }
    f.error = std::isfinite(error) ? error : std::numeric_limits<double>::infinity();
    return f;
  };

  // Basis sets: one basis, or two (of one input or of two), each in both domains.
  std::vector<std::vector<std::size_t>> sets;
  for (std::size_t a = 0; a < bases.size(); ++a) {
    sets.push_back({a});
    for (std::size_t b = a + 1; b < bases.size(); ++b) sets.push_back({a, b});
  }
  std::vector<std::size_t> all(coefficients.size());
  for (std::size_t j = 0; j < all.size(); ++j) all[j] = j;
  std::vector<Fit> ranked;
  for (const auto& b : sets) {
    if (stop()) break;
    ranked.push_back(fit(b, all, Form::Linear, 0));
    if (positive) ranked.push_back(fit(b, all, Form::Exp2, 0));
    if (b.size() == 1)
      for (int d : {1, 2}) ranked.push_back(fit(b, all, Form::Rational, d));
  }
  std::stable_sort(ranked.begin(), ranked.end(),
                   [](const Fit& a, const Fit& b) { return a.error < b.error; });
  const double constant_error = fit({}, {}, Form::Linear, 0).error;

  // The best basis sets again with every choice of at most two coefficient functions: the
  // smallest per-material part that does about as well.
  std::vector<std::vector<std::size_t>> subsets = {{}};
  for (std::size_t a = 0; a < coefficients.size(); ++a) {
    subsets.push_back({a});
    for (std::size_t b = a + 1; b < coefficients.size(); ++b) subsets.push_back({a, b});
  }
  // Per shape (one basis or two, linear or exp2) its best basis sets; each kept with the choice
  // of coefficient functions that fits it best (the fit with all of them only ranks: its
  // constants cancel one another, and float32 would not hold them).
  std::vector<Fit> kept;
  struct Shape {
    std::size_t size;
    Form form;
    int degree;
  };
  const Shape shapes[] = {{1, Form::Linear, 0}, {2, Form::Linear, 0},   {1, Form::Exp2, 0},
                          {2, Form::Exp2, 0},   {1, Form::Rational, 1}, {1, Form::Rational, 2}};
  for (const Shape& shape : shapes) {
    std::size_t taken = 0;
    for (const Fit& r : ranked) {
      if (r.bases.size() != shape.size || r.form != shape.form || r.degree != shape.degree)
        continue;
      if (!std::isfinite(r.error) || taken++ == kUniformStartBases) break;
      if (stop()) break;
      Fit best;
      for (const auto& t : subsets) {
        Fit f = fit(r.bases, t, r.form, r.degree);
        if (f.error < best.error) best = std::move(f);
      }
      if (best.error <= 0.5 * constant_error) kept.push_back(std::move(best));
    }
  }

  std::vector<std::string> out;
  for (const Fit& f : kept) {
    std::size_t at = 0;
    auto coefficient = [&] {
      std::string coef = number(f.c[at++]);
      for (std::size_t j : f.coefficient_set)
        coef += " + " + number(f.c[at++]) + " * " + coefficients[j].text;
      return "(" + coef + ")";
    };
    std::string text;
    if (f.form == Form::Rational) {
      const std::string& b = bases[f.bases.front()].text;
      std::string num = coefficient(), den = "1";
      for (int p = 1; p <= f.degree; ++p)
        num += " + " + coefficient() + " * " + b + (p > 1 ? "^" + std::to_string(p) : "");
      for (int p = 1; p <= f.degree; ++p)
        den += " + " + coefficient() + " * " + b + (p > 1 ? "^" + std::to_string(p) : "");
      text = "(" + num + ") / (" + den + ")";
    } else {
      text = coefficient();
      for (std::size_t k : f.bases) text += " + " + coefficient() + " * " + bases[k].text;
      if (f.form == Form::Exp2) text = "exp2(" + text + ")";
    }
    out.push_back(text);
  }
  return out;
}

}  // namespace shaderfit::search_detail
