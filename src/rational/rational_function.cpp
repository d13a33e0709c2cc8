#include "shaderfit/rational/rational_function.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <system_error>

#include "shaderfit/core/error.hpp"
#include "shaderfit/expr/forward.hpp"
#include "shaderfit/expr/jet.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/expr/print.hpp"
#include "shaderfit/expr/simplify.hpp"

namespace shaderfit::rational {

namespace {

double horner(const std::vector<double>& c, double t) {
  double s = 0;
  for (std::size_t i = c.size(); i-- > 0;) s = s * t + c[i];
  return s;
}

// Postfix builder for the Horner expression.
struct Builder {
  Expression e;
  Expression t;  // the transform's expression

  void constant(double v) { e.nodes.push_back(Node::constant(v)); }
  void op(Op o) { e.nodes.push_back(Node::op_node(o)); }
  void power(int d) {  // t^d
    e.nodes.insert(e.nodes.end(), t.nodes.begin(), t.nodes.end());
    if (d > 1) e.nodes.push_back(Node::ipow(d));
  }
  // c0 + t^(i1 - i0) (c1 + ...) over the nonzero coefficients nz[k..], times t^i0 at the top.
  // A negative coefficient is subtracted, and a last coefficient is written first (0.96 * t^5).
  void horner(const std::vector<double>& c, const std::vector<int>& nz, std::size_t k) {
    const double ck = c[static_cast<std::size_t>(nz[k])];
    if (k + 1 == nz.size()) return constant(ck);
    const int d = nz[k + 1] - nz[k];
    const bool last = k + 2 == nz.size();
    const double cl = c[static_cast<std::size_t>(nz[k + 1])];
    auto product = [&](bool negate_last) {  // t^d (rest), or c_last t^d
      if (last) {
        constant(negate_last ? -cl : cl);
        power(d);
      } else {
        power(d);
        horner(c, nz, k + 1);
      }
      op(Op::Mul);
    };
    if (ck == 0.0) return product(false);
    if (ck < 0) {
      product(false);
      constant(-ck);
      return op(Op::Sub);
    }
    constant(ck);
    product(last && cl < 0);
    op(last && cl < 0 ? Op::Sub : Op::Add);
  }
  void polynomial(const std::vector<double>& c) {
    std::vector<int> nz;
    for (std::size_t i = 0; i < c.size(); ++i)
      if (c[i] != 0.0) nz.push_back(static_cast<int>(i));
    if (nz.empty()) return constant(0.0);
    if (nz.front() == 0) return horner(c, nz, 0);
    // c[0] is 0: t^i0 (c_i0 + ...) is the same recursion from index 0, which adds nothing.
    std::vector<int> with_zero = {0};
    with_zero.insert(with_zero.end(), nz.begin(), nz.end());
    horner(c, with_zero, 0);
  }
};

}  // namespace

Transform Transform::parse(std::string_view text, const std::string& variable,
                           const std::string& source) {
  ParseOptions opts;
  opts.variables = {variable};
  opts.source = source;
  const Expression e = parse_formula(text, opts);
  auto at = [&](double x) { return evaluate_at(e, Jet(x), {}).value(); };
  const double f0 = at(0.0), f1 = at(1.0), f2 = at(2.0), fh = at(-0.5);
  const double scale = f1 - f0;
  const double tol = 1e-12 * (1 + std::abs(f0) + std::abs(scale));
  if (!std::isfinite(f0) || !std::isfinite(scale) || std::abs(f2 - (f0 + 2 * scale)) > tol ||
      std::abs(fh - (f0 - 0.5 * scale)) > tol)
    throw Error("the variable of a form must be affine in " + variable + " (like 1 - " + variable +
                    "), not '" + std::string(text) + "'",
                {source, 1, 1});
  if (scale == 0.0)
    throw Error("the variable '" + std::string(text) + "' is constant", {source, 1, 1});
  return {f0, scale};
}

std::string Transform::text(const std::string& v) const {
  const std::string off = format_number(std::abs(offset));
  if (scale == 1.0) return offset == 0 ? v : v + (offset > 0 ? " + " : " - ") + off;
  if (scale == -1.0) return offset == 0 ? "-" + v : format_number(offset) + " - " + v;
  const std::string term = format_number(std::abs(scale)) + " * " + v;
  if (offset == 0) return (scale < 0 ? "-" : "") + term;
  if (scale < 0) return format_number(offset) + " - " + term;
  return term + (offset > 0 ? " + " : " - ") + off;
}

Expression Transform::expression(const std::string& variable) const {
  ParseOptions opts;
  opts.variables = {variable};
  return parse_formula(text(variable), opts);
}

std::string RationalForm::name(const std::string& v) const {
  std::string s = std::to_string(numerator_degree) + "/" + std::to_string(denominator_degree);
  if (!variable.is_identity()) s += " in " + variable.text(v);
  return s;
}

std::vector<RationalForm> enumerate_forms(int coefficients,
                                          const std::vector<Transform>& transforms) {
  std::vector<Transform> unique;
  for (const Transform& t : transforms)
    if (std::find(unique.begin(), unique.end(), t) == unique.end()) unique.push_back(t);
  if (unique.empty()) unique.push_back(Transform::identity());
  std::vector<RationalForm> out;
  for (const Transform& t : unique)
    for (int n = 0; n < coefficients; ++n) out.push_back({coefficients - 1 - n, n, t});
  return out;
}

RationalForm parse_form(std::string_view text, const std::string& source) {
  auto fail = [&](const std::string& why, std::size_t at) {
    throw Error(why + " in form '" + std::string(text) + "' (expected m/n, e.g. 2/1)",
                {source, 1, static_cast<int>(at) + 1});
  };
  std::size_t i = 0;
  auto number = [&]() {
    while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i]))) ++i;
    const std::size_t start = i;
    if (i < text.size() && text[i] == '-') fail("a degree must be 0 or more", i);
    while (i < text.size() && std::isdigit(static_cast<unsigned char>(text[i]))) ++i;
    if (i == start) fail("expected a degree", start);
    int d = 0;
    const auto parsed = std::from_chars(text.data() + start, text.data() + i, d);
    if (parsed.ec == std::errc::result_out_of_range || d > kMaxIntegerPower)
      fail("a degree above " + std::to_string(kMaxIntegerPower), start);
    while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i]))) ++i;
    return d;
  };
  RationalForm f;
  f.numerator_degree = number();
  if (i < text.size() && text[i] == '/') {
    ++i;
    f.denominator_degree = number();
  }
  if (i != text.size()) fail("unexpected '" + std::string(1, text[i]) + "'", i);
  return f;
}

double Rational::numerator(double x) const { return horner(p, form.variable(x)); }
double Rational::denominator(double x) const { return horner(q, form.variable(x)); }

void Rational::clean(double relative) {
  for (auto* c : {&p, &q}) {
    double big = 0;
    for (double v : *c) big = std::max(big, std::abs(v));
    for (std::size_t i = 0; i < c->size(); ++i)
      if (!(c == &q && i == 0) && std::abs((*c)[i]) < relative * big) (*c)[i] = 0.0;
  }
}

Expression Rational::to_expression(const std::string& variable) const {
  Builder b;
  b.t = form.variable.expression(variable);
  b.polynomial(p);
  bool q_is_one = true;
  for (std::size_t i = 1; i < q.size(); ++i) q_is_one = q_is_one && q[i] == 0.0;
  if (!q_is_one || (!q.empty() && q[0] != 1.0)) {
    b.polynomial(q);
    b.op(Op::Div);
  }
  b.e.variables = {variable};
  b.e.update_lengths();
  return simplify(b.e);
}

std::optional<double> denominator_zero(const Rational& r, Interval d, double relative_floor) {
  if (r.form.denominator_degree == 0 && !r.q.empty() && r.q[0] != 0.0) return std::nullopt;
  const int n = 2048;
  std::vector<double> xs(n + 1), qs(n + 1);
  double big = 0;
  for (int i = 0; i <= n; ++i) {
    xs[i] = i == n ? d.hi : d.lo + d.width() * i / n;
    qs[i] = r.denominator(xs[i]);
    if (!std::isfinite(qs[i])) return xs[i];
    big = std::max(big, std::abs(qs[i]));
  }
  for (int i = 0; i <= n; ++i) {
    if (qs[i] == 0.0) return xs[i];
    if (i < n && (qs[i] < 0) != (qs[i + 1] < 0)) {
      double a = xs[i], b = xs[i + 1], qa = qs[i];
      for (int it = 0; it < 80 && b - a > 1e-15 * (1 + std::abs(a)); ++it) {
        const double m = 0.5 * (a + b), qm = r.denominator(m);
        if ((qm < 0) == (qa < 0)) {
          a = m;
          qa = qm;
        } else {
          b = m;
        }
      }
      return 0.5 * (a + b);
    }
  }
  // No sign change: look for a double root, a minimum of |Q| that touches zero.
  for (int i = 0; i <= n; ++i) {
    const double here = std::abs(qs[i]);
    if ((i > 0 && std::abs(qs[i - 1]) < here) || (i < n && std::abs(qs[i + 1]) < here)) continue;
    double a = xs[std::max(i - 1, 0)], b = xs[std::min(i + 1, n)];
    const double g = 0.5 * (std::sqrt(5.0) - 1);
    for (int it = 0; it < 60; ++it) {
      const double c = b - g * (b - a), e = a + g * (b - a);
      if (std::abs(r.denominator(c)) < std::abs(r.denominator(e)))
        b = e;
      else
        a = c;
    }
    const double m = 0.5 * (a + b);
    if (std::abs(r.denominator(m)) <= relative_floor * big) return m;
  }
  return std::nullopt;
}

}  // namespace shaderfit::rational
