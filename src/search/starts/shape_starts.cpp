#include "search/starts/shape_starts.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <optional>

#include "search/evolution/rewrites.hpp"
#include "search/starts/descent.hpp"
#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/fit/fit.hpp"
#include "shaderfit/fit/linear.hpp"

namespace shaderfit::search_detail {

namespace {

using Column = std::vector<double>;

// A shape's text: '#' for each number, in order of appearance (which is the order parse_formula
// numbers its literals as parameters), 'X' for the input.
std::string filled(std::string_view shape, std::string_view x, const std::vector<double>& values) {
  std::string out;
  std::size_t k = 0;
  for (char c : shape) {
    if (c == '#')
      out += "(" + fmt::format("{:.17g}", k < values.size() ? values[k++] : 0.0) + ")";
    else if (c == 'X')
      out += x;
    else
      out += c;
  }
  return out;
}

// text parsed over `names` with its literals free; nullopt when it does not parse into exactly
// `count` parameters.
std::optional<Expression> parsed_free(const std::string& text,
                                      const std::vector<std::string>& names, std::size_t count) {
  ParseOptions po;
  po.variables = names;
  po.literals_as_parameters = true;
  po.source = "shape";
  try {
    Expression e = parse_formula(text, po);
    if (e.parameters.size() != count) return std::nullopt;
    return e;
  } catch (const Error&) {
    return std::nullopt;
  }
}

Column values_of(const Expression& e, const SearchProblem& rows) {
  std::vector<const double*> cols;
  for (const Column& c : rows.inputs) cols.push_back(c.data());
  Column out(rows.target.size());
  evaluate(e, cols, out);
  return out;
}

bool all_finite(const Column& v) {
  return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
}

std::vector<double> least_squares(const std::vector<Column>& columns, const Column& y,
                                  const Column& w = {}) {
  std::vector<const double*> p;
  for (const Column& c : columns) p.push_back(c.data());
  return solve_least_squares(p, y, w);
}

Column mapped(const Column& x, double (*f)(double, double), double a) {
  Column out(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) out[i] = f(x[i], a);
  return out;
}

// RMS of (f - t) / t; +inf where f is not finite.
double relative_rms(const Column& f, const Column& t) {
  double s = 0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    const double d = (f[i] - t[i]) / t[i];
    s += d * d;
  }
  const double r = std::sqrt(s / static_cast<double>(t.size()));
  return std::isfinite(r) ? r : HUGE_VAL;
}

// A one-input shape with its starting values. `scaled`: how a factor S is taken in, by
// multiplying its first `scaled` numbers (> 0), or by adding log2 S to its first (-1: an exp2);
// 0: it is not.
struct Shape {
  std::string text;
  std::vector<double> values;
  int scaled = 0;
};

// The degree of each varying input's polynomial in the split of the target's log.
constexpr std::size_t kSplitDegree = 6;

// The powers tried for a fitted exponent before it is refined.
constexpr double kPowers[] = {-3, -2, -1.5, -1, -0.5, 0.5, 1.5, 2, 2.5, 3, 4, 5};

// The one-input shapes of the header with starting values fitted to samples t (> 0) at x.
std::vector<Shape> one_input_shapes(const Column& x, const Column& t) {
  const std::size_t n = x.size();
  const Column one(n, 1.0);
  const double lo = *std::min_element(x.begin(), x.end());
  const double hi = *std::max_element(x.begin(), x.end());
  const Column x2 = mapped(
      x, [](double v, double) { return v * v; }, 0);
  Column lt(n);
  for (std::size_t i = 0; i < n; ++i) lt[i] = std::log2(t[i]);
  std::vector<Shape> out;
  out.push_back({"# + # * X", least_squares({one, x}, t), 2});
  out.push_back({"# + X * (# + # * X)", least_squares({one, x, x2}, t), 3});
  out.push_back({"exp2(# + # * X)", least_squares({one, x}, lt, t), -1});
  out.push_back({"exp2(# + X * (# + # * X))", least_squares({one, x, x2}, lt, t), -1});
  // (b0 + b1 u)^p for u = x, x^2: t^(1/p) = b0 + b1 u on a grid of p, the best by its error in t.
  for (const auto& [u, text] : {std::pair{&x, "exp2(# * log2(# + # * X))"},
                                std::pair{&x2, "exp2(# * log2(# + # * X^2))"}}) {
    double best = HUGE_VAL;
    std::vector<double> values;
    for (double p : kPowers) {
      const Column root = mapped(
          t, [](double v, double q) { return std::pow(v, 1 / q); }, p);
      const std::vector<double> c = least_squares({one, *u}, root);
      Column f(n);
      for (std::size_t i = 0; i < n; ++i) f[i] = std::pow(c[0] + c[1] * (*u)[i], p);
      const double e = relative_rms(f, t);
      if (e < best) {
        best = e;
        values = {p, c[0], c[1]};
      }
    }
    if (!values.empty()) out.push_back({text, values});
  }
  // Schlick-like: a + b (c - x)^5 and a + b (c - x)^k with c just above the largest x, so that
  // the power's derivatives stay finite; and the exp2 form a + b exp2(k x).
  const double c = std::max(1.0, hi + 1e-3 * (hi - lo));
  const Column from_c = mapped(
      x, [](double v, double cc) { return cc - v; }, c);
  out.push_back({"# + # * (# - X)^5", {}, 2});
  {
    const std::vector<double> ab =
        least_squares({one, mapped(
                                from_c, [](double v, double) { return std::pow(v, 5); }, 0)},
                      t);
    out.back().values = {ab[0], ab[1], c};
  }
  // a + b g_k(x) by least squares for each k of a grid, the best by its relative error.
  const auto best_on_grid = [&](std::initializer_list<double> grid,
                                const std::function<Column(double)>& g) {
    double best = HUGE_VAL;
    std::vector<double> values;  // a, b, k
    for (double k : grid) {
      const Column gk = g(k);
      const std::vector<double> ab = least_squares({one, gk}, t);
      Column f(n);
      for (std::size_t i = 0; i < n; ++i) f[i] = ab[0] + ab[1] * gk[i];
      const double e = relative_rms(f, t);
      if (e < best) {
        best = e;
        values = {ab[0], ab[1], k};
      }
    }
    return values;
  };
  std::vector<double> schlick =
      best_on_grid({0.5, 1.0, 1.5, 2.0, 3.0, 4.0, 5.0, 6.0}, [&](double k) {
        return mapped(
            from_c, [](double v, double q) { return std::pow(v, q); }, k);
      });
  if (!schlick.empty()) {
    schlick.push_back(c);
    out.push_back({"# + # * exp2(# * log2(# - X))", schlick, 2});
  }
  const double span = hi > lo ? hi - lo : 1.0;
  const std::vector<double> exponential = best_on_grid(
      {-16.0, -8.0, -4.0, -2.0, -1.0, -0.5, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0}, [&](double k) {
        return mapped(
            x, [](double v, double q) { return std::exp2(q * v); }, k / span);
      });
  if (!exponential.empty())
    out.push_back(
        {"# + # * exp2(# * X)", {exponential[0], exponential[1], exponential[2] / span}, 2});
  // (a + b x) / (1 + d x), linearised: t = a + b x - d x t.
  {
    Column xt(n);
    for (std::size_t i = 0; i < n; ++i) xt[i] = -x[i] * t[i];
    const std::vector<double> c3 = least_squares({one, x, xt}, t);
    if (1 + c3[2] * lo > 0 && 1 + c3[2] * hi > 0)
      out.push_back({"(# + # * X) / (# + # * X)", {c3[0], c3[1], 1.0, c3[2]}, 2});
  }
  return out;
}

// A one-input shape fitted to a factor's samples: its text with the fitted values, its cost and
// its relative RMS error there.
struct Factor {
  std::string shape;
  std::vector<double> values;
  int scaled = 0;  // Shape::scaled
  double cost = 0, error = HUGE_VAL;
};

// e with each parameter p replaced by p + sum over the per-material variables u of
// (q u + r u^2), the new parameters at 0: a coefficient per material, free per pixel.
Expression per_material(const Expression& e, const std::vector<int>& uniform) {
  if (uniform.empty()) return e;
  Expression r;
  r.variables = e.variables;
  r.parameters = e.parameters;
  r.parameter_values = e.parameter_values;
  const auto fresh = [&] {
    r.parameters.push_back("p" + std::to_string(r.parameters.size()));
    r.parameter_values.push_back(0.0);
    return Node::parameter(static_cast<int>(r.parameters.size() - 1));
  };
  for (const Node& n : e.nodes) {
    r.nodes.push_back(n);
    // Each parameter gains two per uniform input while the fit can take them.
    if (n.op != Op::Param || r.parameters.size() + 2 * uniform.size() > kMaxFitParameters) continue;
    for (int u : uniform)
      for (int power : {1, 2}) {
        r.nodes.push_back(fresh());
        r.nodes.push_back(Node::variable(u));
        if (power == 2) r.nodes.push_back(Node::ipow(2));
        r.nodes.push_back(Node::op_node(Op::Mul));
        r.nodes.push_back(Node::op_node(Op::Add));
      }
  }
  r.update_lengths();
  return r;
}

}  // namespace

std::vector<StartFormula> shape_starts(SearchContext& ctx, double until_s) {
  const SearchOptions& options = ctx.options;
  const SearchProblem rows = descent_rows(ctx.problem);
  const std::size_t n = rows.target.size(), inputs = rows.inputs.size();
  if (n < 16 || !std::all_of(rows.target.begin(), rows.target.end(),
                             [](double v) { return v > 0 && std::isfinite(v); }))
    return {};
  std::vector<std::string> names;
  for (std::size_t k = 0; k < inputs; ++k) names.push_back("x" + std::to_string(k));
  std::vector<int> varying, uniform;
  for (std::size_t k = 0; k < inputs; ++k) {
    const bool u = std::find(options.uniform.begin(), options.uniform.end(),
                             ctx.problem.input_names[k]) != options.uniform.end();
    (u ? uniform : varying).push_back(static_cast<int>(k));
  }
  if (varying.empty()) return {};
  const auto out_of_time = [&] { return ctx.should_stop() || ctx.elapsed() >= until_s; };
  const Column one(n, 1.0);
  const auto power_of = [](const Column& v, int p) {
    Column out(v.size());
    for (std::size_t i = 0; i < v.size(); ++i) out[i] = std::pow(v[i], p);
    return out;
  };

  // The log split into polynomials of one input each (per-material inputs: quadratics), weighted so
  // that an error in log2 counts as the loss counts it (relative losses: alike on every row).
  const bool relative =
      options.loss == Loss::Relative || options.loss == Loss::Log || options.loss == Loss::MaxRel;
  Column ly(n), w(n);
  for (std::size_t r = 0; r < n; ++r) {
    ly[r] = std::log2(rows.target[r]);
    w[r] = (rows.weights.empty() ? 1.0 : rows.weights[r]) *
           (relative ? 1.0 : rows.target[r] * rows.target[r]);
  }
  std::vector<Column> design{one};
  for (int v : varying)
    for (std::size_t p = 1; p <= kSplitDegree; ++p)
      design.push_back(power_of(rows.inputs[v], static_cast<int>(p)));
  for (int u : uniform)
    for (int p = 1; p <= 2; ++p) design.push_back(power_of(rows.inputs[u], p));
  const std::vector<double> split = least_squares(design, ly, w);
  if (!all_finite(split)) return {};

  // Each varying input's factor 2^h(x), h its cubic, searched alone: the one-input shapes
  // fitted to it (relative error), the best at each cost kept.
  SearchOptions alone = options;
  alone.uniform.clear();
  alone.loss = Loss::Relative;
  std::vector<std::vector<Factor>> factors(varying.size());
  for (std::size_t j = 0; j < varying.size() && !out_of_time(); ++j) {
    const Column& xv = rows.inputs[static_cast<std::size_t>(varying[j])];
    const double lo = *std::min_element(xv.begin(), xv.end());
    const double hi = *std::max_element(xv.begin(), xv.end());
    if (!(hi > lo)) continue;
    SearchProblem samples;
    samples.input_names = {"x0"};
    samples.inputs.resize(1);
    double mean_h = 0;
    Column h(kShapeFactorSamples);
    for (std::size_t i = 0; i < kShapeFactorSamples; ++i) {
      const double x = lo + (hi - lo) * static_cast<double>(i) / (kShapeFactorSamples - 1);
      samples.inputs[0].push_back(x);
      h[i] = 0;
      for (std::size_t p = kSplitDegree; p >= 1; --p)
        h[i] = (h[i] + split[p + kSplitDegree * j]) * x;
      mean_h += h[i] / kShapeFactorSamples;
    }
    for (double v : h) samples.target.push_back(std::exp2(v - mean_h));
    const double spread =
        *std::max_element(h.begin(), h.end()) - *std::min_element(h.begin(), h.end());
    if (spread < 1e-3) continue;  // a factor of about 1: the input is left out
    std::vector<Factor> fitted;
    for (const Shape& s : one_input_shapes(samples.inputs[0], samples.target)) {
      if (!all_finite(s.values)) continue;
      const std::optional<Expression> e =
          parsed_free(filled(s.text, "x0", s.values), {"x0"}, s.values.size());
      if (!e) continue;
      const Expression f = refit_on_rows(*e, alone, samples);
      const double error = relative_rms(values_of(f, samples), samples.target);
      if (!std::isfinite(error)) continue;
      fitted.push_back({s.text, f.parameter_values, s.scaled, formula_cost(f, alone), error});
    }
    // The cheapest at each error: a Pareto set by cost, at most kShapeFormsPerFactor (its
    // cheapest and its most accurate halves).
    std::sort(fitted.begin(), fitted.end(), [](const Factor& a, const Factor& b) {
      return a.cost != b.cost ? a.cost < b.cost : a.error < b.error;
    });
    std::vector<Factor> pareto;
    for (Factor& f : fitted)
      if (pareto.empty() || f.error < pareto.back().error) pareto.push_back(std::move(f));
    if (pareto.size() > kShapeFormsPerFactor) {
      const std::size_t half = kShapeFormsPerFactor / 2;
      pareto.erase(pareto.begin() + static_cast<std::ptrdiff_t>(half),
                   pareto.end() - static_cast<std::ptrdiff_t>(kShapeFormsPerFactor - half));
    }
    factors[j] = std::move(pareto);
  }

  // Candidates as text over x0, x1, ... given their scale S: the products of the factors (each
  // input's factor or none; S taken into a factor where one takes it in) and the powers of a
  // quadratic in the varying inputs.
  using Candidate = std::function<std::string(double)>;
  std::vector<Candidate> texts;
  std::vector<std::size_t> radix;
  for (const auto& f : factors) radix.push_back(f.size() + 1);
  std::vector<std::size_t> digit(varying.size(), 0);
  while (true) {
    std::size_t k = 0;
    while (k < digit.size() && ++digit[k] == radix[k]) digit[k++] = 0;
    if (k == digit.size()) break;
    std::vector<std::pair<std::string, Factor>> parts;
    for (std::size_t j = 0; j < digit.size(); ++j)
      if (digit[j] > 0)
        parts.push_back({names[static_cast<std::size_t>(varying[j])], factors[j][digit[j] - 1]});
    texts.push_back([parts](double scale) {
      std::string text;
      bool taken = false;
      for (auto [x, f] : parts) {
        if (!taken && f.scaled > 0) {
          for (int v = 0; v < f.scaled; ++v) f.values[static_cast<std::size_t>(v)] *= scale;
          taken = true;
        } else if (!taken && f.scaled < 0 && scale > 0) {
          f.values[0] += std::log2(scale);
          taken = true;
        }
        text += (text.empty() ? "(" : " * (") + filled(f.shape, x, f.values) + ")";
      }
      return taken ? text : fmt::format("({:.17g}) * {}", scale, text);
    });
  }
  // (b0 + sum b_k m_k)^p over the monomials m of degree 1 (and 2) in the varying inputs.
  for (int degree : {1, 2}) {
    std::vector<Column> monomials{one};
    std::vector<std::string> monomial_texts;
    for (std::size_t a = 0; a < varying.size(); ++a) {
      const Column& xa = rows.inputs[static_cast<std::size_t>(varying[a])];
      monomials.push_back(xa);
      monomial_texts.push_back(names[static_cast<std::size_t>(varying[a])]);
      if (degree < 2) continue;
      for (std::size_t b = a; b < varying.size(); ++b) {
        const Column& xb = rows.inputs[static_cast<std::size_t>(varying[b])];
        Column m(n);
        for (std::size_t r = 0; r < n; ++r) m[r] = xa[r] * xb[r];
        monomials.push_back(std::move(m));
        monomial_texts.push_back(names[static_cast<std::size_t>(varying[a])] + " * " +
                                 names[static_cast<std::size_t>(varying[b])]);
      }
    }
    double best = HUGE_VAL;
    std::string best_text;
    for (double p : kPowers) {
      Column root(n);
      for (std::size_t r = 0; r < n; ++r) root[r] = std::pow(rows.target[r], 1 / p);
      const std::vector<double> c = least_squares(monomials, root);
      if (!all_finite(c)) continue;
      Column f(n);
      bool positive = true;
      for (std::size_t r = 0; r < n && positive; ++r) {
        double b = 0;
        for (std::size_t m = 0; m < monomials.size(); ++m) b += c[m] * monomials[m][r];
        positive = b > 0;
        f[r] = std::pow(b, p);
      }
      const double e = positive ? relative_rms(f, rows.target) : HUGE_VAL;
      if (!(e < best)) continue;
      best = e;
      std::string base = fmt::format("{:.17g}", c[0]);
      for (std::size_t m = 0; m < monomial_texts.size(); ++m)
        base += fmt::format(" + ({:.17g}) * {}", c[m + 1], monomial_texts[m]);
      best_text = fmt::format("exp2(({:.17g}) * log2({}))", p, base);
    }
    if (!best_text.empty())
      texts.push_back(
          [best_text](double scale) { return fmt::format("({:.17g}) * {}", scale, best_text); });
  }

  // Each candidate with its best scale, screened on the rows; the best few at each cost refitted
  // together, with per-material coefficients under --uniform.
  std::map<double, std::vector<std::pair<double, Expression>>> screened;
  for (const Candidate& candidate : texts) {
    if (out_of_time()) break;
    const std::string text = candidate(1.0);
    ParseOptions po;
    po.variables = names;
    po.source = "shape";
    Expression e;
    try {
      e = parse_formula(text, po);
    } catch (const Error&) {
      continue;
    }
    const Column f = values_of(e, rows);
    if (!all_finite(f)) continue;
    double fy = 0, ff = 0;
    for (std::size_t r = 0; r < n; ++r) {
      fy += f[r] * rows.target[r];
      ff += f[r] * f[r];
    }
    if (!(ff > 0)) continue;
    const std::string scaled = candidate(fy / ff);
    ParseOptions free = po;
    free.literals_as_parameters = true;
    Expression x;
    try {
      x = parse_formula(scaled, free);
    } catch (const Error&) {
      continue;
    }
    x.variables = ctx.problem.input_names;
    const double loss = rows_loss(x, options.loss, rows);
    if (!std::isfinite(loss)) continue;
    screened[formula_cost(x, options)].push_back({loss, std::move(x)});
  }
  std::vector<StartFormula> out;
  for (auto& [cost, level] : screened) {
    std::stable_sort(level.begin(), level.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    for (std::size_t k = 0; k < level.size() && k < kShapeRefitsPerCost; ++k) {
      if (out_of_time()) break;
      Expression e = refit_on_rows(per_material(level[k].second, uniform), options, rows);
      e = cheapest_form(std::move(e), options, rows);
      if (!std::isfinite(rows_loss(e, options.loss, rows))) continue;
      StartFormula s;
      s.written = e;
      s.free = std::move(e);
      s.fitted = true;
      s.origin = SearchPhase::Shape;
      out.push_back(std::move(s));
    }
  }
  return out;
}

}  // namespace shaderfit::search_detail
