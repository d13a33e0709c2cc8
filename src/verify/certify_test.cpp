#include "shaderfit/verify/certify.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "shaderfit/core/error.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/reference/domain.hpp"
#include "shaderfit/reference/language.hpp"
#include "verify/interval.hpp"
#include "verify/reference_test_util.hpp"

namespace shaderfit {
namespace {

using reference::DomainAxis;
using reference::ReferenceFunction;

using test::make_reference;

std::vector<std::string> variables_of(const ReferenceFunction& f) {
  std::vector<std::string> v;
  for (const DomainAxis& a : f.domain) v.push_back(a.name);
  return v;
}

Expression formula(const std::string& text, const ReferenceFunction& f) {
  ParseOptions o;
  o.variables = variables_of(f);
  return parse_formula(text, o);
}

// The formula in double at one point, with op.hpp's meaning.
double eval_double(const Expression& e, std::span<const double> x) {
  std::vector<double> stack;
  for (const Node& n : e.nodes) {
    if (n.op == Op::Const) {
      stack.push_back(n.value);
    } else if (n.op == Op::Param) {
      stack.push_back(e.parameter_values[static_cast<std::size_t>(n.index)]);
    } else if (n.op == Op::Var) {
      stack.push_back(x[static_cast<std::size_t>(n.index)]);
    } else {
      const std::size_t k = n.arity;
      const double a = stack[stack.size() - k];
      const double b = k > 1 ? stack[stack.size() - k + 1] : 0.0;
      const double c = k > 2 ? stack[stack.size() - k + 2] : 0.0;
      double r = 0;
      if (n.op == Op::IPow) {
        r = apply_ipow(a, n.index);
      } else if (k == 1) {
        r = apply_unary(n.op, a);
      } else if (k == 2) {
        r = apply_binary(n.op, a, b);
      } else {
        r = apply_ternary(n.op, a, b, c);
      }
      stack.resize(stack.size() - k);
      stack.push_back(r);
    }
  }
  return stack.back();
}

// max |formula - reference| over a uniform grid of n points per axis (1-D or 2-D).
double dense_max(const Expression& e, const ReferenceFunction& f, int n) {
  double worst = 0;
  const std::size_t dims = f.domain.size();
  std::vector<double> x(dims);
  const long total = dims == 1 ? n : static_cast<long>(n) * n;
  for (long k = 0; k < total; ++k) {
    long rest = k;
    for (std::size_t i = 0; i < dims; ++i) {
      const long j = rest % n;
      rest /= n;
      x[i] = f.domain[i].lo + (f.domain[i].hi - f.domain[i].lo) * static_cast<double>(j) / (n - 1);
    }
    worst = std::max(worst, std::abs(eval_double(e, x) - f.target_at(x)));
  }
  return worst;
}

// Abramowitz and Stegun 4.4.45 on [0, 1], reflected for x < 0 by select or by copysign.
std::string acos_r() {
  const std::string a = "abs(x)";
  return "sqrt(1 - " + a + ") * (1.5707288 + " + a + " * (-0.2121144 + " + a +
         " * (0.0742610 - 0.0187293 * " + a + ")))";
}

void expect_tight(const Certificate& c, double dense, double ratio, const char* name) {
  std::printf("%s: bound %.9g attained %.9g dense %.9g ratio %.5f boxes %zu time %.3f s %s\n", name,
              c.bound, c.attained, dense, c.bound / dense, c.boxes, c.time_s, c.note.c_str());
  EXPECT_GE(c.bound, dense) << name;
  EXPECT_LE(c.attained, c.bound) << name;
  EXPECT_LE(c.bound, ratio * dense) << name << ": " << c.note;
}

TEST(Certify, AcosAbramowitzStegunSelect) {
  const ReferenceFunction f = make_reference("acos(x)", {"x=-1:1"});
  const Expression e = formula("select(x >= 0, " + acos_r() + ", pi - " + acos_r() + ")", f);
  const Certificate c = certify(e, {"x"}, f);
  EXPECT_TRUE(c.converged) << c.note;
  EXPECT_TRUE(c.note.empty());
  expect_tight(c, dense_max(e, f, 1000001), 1.05, "acos select");
  EXPECT_LT(c.time_s, 2.0);
  // The largest error is at x = 0: |r(0) - pi/2| = 6.75e-5.
  ASSERT_EQ(c.attained_point.size(), 1u);
  EXPECT_NEAR(c.attained_point[0], 0.0, 1e-3);
}

TEST(Certify, AcosAbramowitzStegunCopysign) {
  const ReferenceFunction f = make_reference("acos(x)", {"x=-1:1"});
  const Expression e =
      formula("1.5707963267948966 - copysign(1.5707963267948966 - " + acos_r() + ", x)", f);
  const Certificate c = certify(e, {"x"}, f);
  EXPECT_TRUE(c.converged) << c.note;
  expect_tight(c, dense_max(e, f, 1000001), 1.05, "acos copysign");
}

TEST(Certify, Exp2Polynomial) {
  const ReferenceFunction f = make_reference("exp2(x)", {"x=0:1"});
  const Expression e = formula(
      "1.0000035 + x * (0.69297292 + x * (0.24160436 + x * (0.051744998 + x * 0.013670309)))", f);
  const Certificate c = certify(e, {"x"}, f);
  EXPECT_TRUE(c.converged) << c.note;
  expect_tight(c, dense_max(e, f, 1000001), 1.05, "exp2");
}

TEST(Certify, FormulasWithAsinAcosAtanAtan2TanhErf) {
  // The search's operators asin ... erf in the formula, against references of the same functions.
  const ReferenceFunction f1 = make_reference("erf(x)", {"x=-2:2"});
  const Expression e1 = formula("tanh(1.202 * x) + 0.003 * erf(3 * x)", f1);
  const Certificate c1 = certify(e1, {"x"}, f1);
  expect_tight(c1, dense_max(e1, f1, 1000001), 1.05, "tanh and erf");
  const ReferenceFunction f2 = make_reference("acos(x)", {"x=-0.9:0.9"});
  const Expression e2 = formula("1.5707963 - asin(x) - 0.01 * atan(3 * x) + 0.001 * acos(x)", f2);
  const Certificate c2 = certify(e2, {"x"}, f2);
  expect_tight(c2, dense_max(e2, f2, 1000001), 1.05, "asin, acos, atan");
  const ReferenceFunction f3 = make_reference("atan(y / x)", {"x=0.2:1", "y=-1:1"});
  const Expression e3 = formula("atan2(y, x) * 0.99 + 0.01 * atan2(x, 2 - y)", f3);
  CertifyOptions o;
  o.time_limit_s = 20;
  const Certificate c3 = certify(e3, {"x", "y"}, f3, o);
  expect_tight(c3, dense_max(e3, f3, 2001), 1.2, "atan2 2-D");
}

TEST(Certify, PiecewiseReferenceSrgb) {
  // sRGB encoding: a select in the reference, pow with a fractional exponent down to 0.
  const ReferenceFunction f =
      make_reference("x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1 / 2.4) - 0.055", {"x=0:1"});
  const Expression e = formula("select(x <= 0.003, 12.92 * x, 1.055 * pow(x, 0.4167) - 0.055)", f);
  const Certificate c = certify(e, {"x"}, f);
  EXPECT_TRUE(c.converged) << c.note;
  expect_tight(c, dense_max(e, f, 1000001), 1.05, "srgb");
}

TEST(Certify, TwoDimensionalFresnel) {
  // Schlick's approximation against the exact dielectric Fresnel reflectance, over the cosine
  // and the normal-incidence reflectance F0.
  const ReferenceFunction f = make_reference(
      "0.5 * ((g - c) / (g + c))^2 * (1 + ((c * (g + c) - 1) / (c * (g - c) + 1))^2)",
      {"c=0:1", "f0=0.02:0.1"},
      {"eta = (1 + sqrt(f0)) / (1 - sqrt(f0))", "g = sqrt(eta^2 - 1 + c^2)"});
  const Expression e = formula("f0 + (1 - f0) * (1 - c)^5", f);
  CertifyOptions o;
  o.time_limit_s = 20;
  const Certificate c = certify(e, {"c", "f0"}, f, o);
  expect_tight(c, dense_max(e, f, 2001), 1.2, "fresnel 2-D");
}

TEST(Certify, TwoDimensionalSmithG1) {
  const ReferenceFunction f =
      make_reference("2 * v / (v + sqrt(a^2 + (1 - a^2) * v^2))", {"v=0:1", "a=0.1:1"});
  const Expression e = formula("v / (v * (1 - 0.5 * a) + 0.5 * a)", f);
  CertifyOptions o;
  o.time_limit_s = 20;
  const Certificate c = certify(e, {"v", "a"}, f, o);
  expect_tight(c, dense_max(e, f, 2001), 1.2, "smith g1 2-D");
}

TEST(Certify, FormulaOverDefinitions) {
  // The formula's input is a definition of the reference: derivatives flow through both.
  const ReferenceFunction f = make_reference("sin(t)", {"x=0:1"}, {"t = 1.5 * x"});
  ParseOptions po;
  po.variables = {"t"};
  const Expression e = parse_formula("t - t^3 / 6 + t^5 / 120", po);
  const Certificate c = certify(e, {"t"}, f);
  EXPECT_TRUE(c.converged) << c.note;
  double dense = 0;
  for (int k = 0; k <= 100000; ++k) {
    const double t = 1.5 * k / 100000.0;
    dense = std::max(dense, std::abs(t - t * t * t / 6 + std::pow(t, 5) / 120 - std::sin(t)));
  }
  expect_tight(c, dense, 1.05, "definitions");
}

TEST(Certify, ExactFormulaConverges) {
  // The bound shrinks to CertifyOptions::resolution times the reference's size.
  const ReferenceFunction f = make_reference("x^2 - 1", {"x=-1:-0.9"});
  const Certificate c = certify(formula("(x - 1) * (x + 1)", f), {"x"}, f);
  EXPECT_TRUE(c.converged) << c.note;
  EXPECT_LE(c.bound, 0.19 * CertifyOptions{}.resolution);
  EXPECT_EQ(c.attained, 0.0);
}

TEST(Certify, SingularityInsideGivesInfinity) {
  const ReferenceFunction f = make_reference("x", {"x=0:1"});
  CertifyOptions o;
  o.time_limit_s = 5;
  const Certificate c = certify(formula("1 / (x - 0.3)", f), {"x"}, f, o);
  EXPECT_TRUE(std::isinf(c.bound));
  EXPECT_FALSE(c.converged);
  EXPECT_NE(c.note.find("0.3"), std::string::npos) << c.note;
  EXPECT_LT(c.time_s, 2.0);
  // At a point the bisection reaches: found there, at once.
  const ReferenceFunction g = make_reference("x", {"x=-1:1"});
  const Certificate d = certify(formula("1 / x", g), {"x"}, g, o);
  EXPECT_TRUE(std::isinf(d.bound));
  EXPECT_NE(d.note.find("the formula"), std::string::npos) << d.note;
  EXPECT_NE(d.note.find("x = 0"), std::string::npos) << d.note;
}

TEST(Certify, NanFormulaGivesInfinity) {
  const ReferenceFunction f = make_reference("x", {"x=0:1"});
  const Certificate c = certify(formula("sqrt(x - 0.5)", f), {"x"}, f);
  EXPECT_TRUE(std::isinf(c.bound));
  EXPECT_FALSE(c.converged);
  EXPECT_NE(c.note.find("the formula may be undefined"), std::string::npos) << c.note;
}

TEST(Certify, NanReferenceIsNamed) {
  const ReferenceFunction f = make_reference("log(x - 0.25)", {"x=0:1"});
  const Certificate c = certify(formula("x", f), {"x"}, f);
  EXPECT_TRUE(std::isinf(c.bound));
  EXPECT_NE(c.note.find("the reference"), std::string::npos) << c.note;
}

TEST(Certify, ClampedSqrtInReferenceStaysFinite) {
  // sqrt(x > 0 ? x : 0): the select is a max of the compared values, so the sqrt never sees the
  // negative part of a box straddling 0.
  const ReferenceFunction f = make_reference("sqrt(x > 0 ? x : 0)", {"x=-1:1"});
  const Certificate c = certify(formula("sqrt(max(x, 0)) + 0.001", f), {"x"}, f);
  EXPECT_TRUE(c.converged) << c.note;
  EXPECT_NEAR(c.bound, 0.001, 1e-5);
}

TEST(Certify, Errors) {
  const ReferenceFunction f = make_reference("acos(x)", {"x=-1:1"});
  EXPECT_THROW((void)certify(formula("x", f), {"y"}, f), Error);
  CertifyOptions o;
  o.precision_bits = 24;
  EXPECT_THROW((void)certify(formula("x", f), {"x"}, f, o), Error);
}

TEST(Certify, SqrtOfPolynomialZeroAtTheEnd) {
  // p(1) = 0 exactly (a fitted polynomial the search snapped), p decreasing: every box touching
  // x = 1 has p's natural enclosure below 0; its monotonicity gives the exact end p(1) = 0.
  const ReferenceFunction f = make_reference("acos(x)", {"x=-1:1"});
  const Expression e = formula(
      "1.5707963267948966 - copysign(1.5707963267948966 - sqrt(2.449015377016785 - abs(x) * "
      "(2.9432667277882403 - abs(x) * 0.4942513507714552)), x)",
      f);
  const Certificate c = certify(e, {"x"}, f);
  EXPECT_TRUE(c.converged) << c.note;
  expect_tight(c, dense_max(e, f, 1000001), 1.05, "sqrt(p), p(1) = 0");
}

TEST(Certify, BuiltinReferences) {
  // The built-in templates' branches go through reference::choose: the same bound as the
  // reference written as a formula.
  const ReferenceFunction builtin = make_reference("fresnel_dielectric_f0(c, 0.04)", {"c=0:1"});
  const ReferenceFunction written = make_reference(
      "0.5 * ((g - c) / (g + c))^2 * (1 + ((c * (g + c) - 1) / (c * (g - c) + 1))^2)", {"c=0:1"},
      {"g = sqrt(1.25 + c^2)"});
  const std::string schlick = "0.04 + 0.96 * (1 - c)^5";
  const Certificate a = certify(formula(schlick, builtin), {"c"}, builtin);
  const Certificate b = certify(formula(schlick, written), {"c"}, written);
  EXPECT_TRUE(a.converged) << a.note;
  EXPECT_NEAR(a.bound, b.bound, 0.011 * b.bound);
  expect_tight(a, dense_max(formula(schlick, builtin), builtin, 100001), 1.05, "fresnel builtin");
  // Smith G1 and GGX D over two variables, a conductor with its ratio_or_one.
  const ReferenceFunction g1 = make_reference("smith_ggx_g1(v, a)", {"v=0:1", "a=0.1:1"});
  const Expression schlick_g1 = formula("v / (v * (1 - 0.5 * a) + 0.5 * a)", g1);
  expect_tight(certify(schlick_g1, {"v", "a"}, g1), dense_max(schlick_g1, g1, 1001), 1.2,
               "smith builtin");
  const ReferenceFunction metal = make_reference("fresnel_exact(c, 0.2, 3)", {"c=0:1"});
  const Expression m = formula("0.93 + 0.07 * (1 - c)^5", metal);
  const Certificate cm = certify(m, {"c"}, metal);
  EXPECT_TRUE(cm.converged) << cm.note;
  expect_tight(cm, dense_max(m, metal, 100001), 1.05, "conductor builtin");
}

// Random small formulas against a few references, in one and two variables: the bound holds at
// 10^5 random points (up to the double evaluation's own rounding), and is finite only where the
// formula is.
TEST(Certify, RigourOnRandomFormulas) {
  std::mt19937_64 rng(26);
  const std::vector<std::pair<std::string, std::vector<std::string>>> references = {
      {"sin(3 * x)", {"x=-1:1"}},
      {"exp(x) - 1", {"x=-1:1"}},
      {"atan(4 * x)", {"x=-1:1"}},
      {"erf(2 * x)", {"x=-1:1"}},
      {"abs(x - 0.2)", {"x=-1:1"}},
      {"x > 0.3 ? x * x : 0.5 * x", {"x=-1:1"}},
      {"floor(4 * x) / 4", {"x=-1:1"}},
      {"sqrt(x)", {"x=0:1"}},
      {"acos(x)", {"x=-1:1"}},
      {"fmod(5 * x, 0.7)", {"x=0.1:1"}},
      {"atan2(x, x - 0.5)", {"x=-1:-0.1"}},
      {"cbrt(x) + tanh(2 * x)", {"x=-1:1"}},
      {"sin(3 * x * y)", {"x=-1:1", "y=0:1"}},
      {"exp(x - y) / (1 + y)", {"x=-1:1", "y=0:1"}},
      {"hypot(x, y - 0.3)", {"x=-1:1", "y=0:1"}},
      {"x > y ? x : y * y", {"x=-1:1", "y=0:1"}},
      {"atan2(y + 1.5, x)", {"x=-1:1", "y=0:1"}},
      {"x * sqrt(y) + pow(y + 0.5, x)", {"x=-1:1", "y=0:1"}}};
  std::uniform_real_distribution<double> unit(0, 1);
  std::vector<std::string> vars;
  std::function<std::string(int)> random_formula = [&](int depth) -> std::string {
    const int choice = depth <= 0 ? static_cast<int>(rng() % 2) : static_cast<int>(rng() % 14);
    char c[32];
    std::snprintf(c, sizeof c, "%.3f", 4 * unit(rng) - 2);
    const std::string& v = vars[rng() % vars.size()];
    switch (choice) {
      case 0: return v;
      case 1: return c;
      case 2: return "(" + random_formula(depth - 1) + " + " + random_formula(depth - 1) + ")";
      case 3: return "(" + random_formula(depth - 1) + " * " + random_formula(depth - 1) + ")";
      case 4: return "(" + random_formula(depth - 1) + " - " + random_formula(depth - 1) + ")";
      case 5: return "(" + random_formula(depth - 1) + " / (2.5 + sin(" + v + ")))";
      case 6: return "abs(" + random_formula(depth - 1) + ")";
      case 7: return "min(" + random_formula(depth - 1) + ", " + random_formula(depth - 1) + ")";
      case 8: return "saturate(" + random_formula(depth - 1) + ")";
      case 9: return "exp2(" + random_formula(depth - 1) + ")";
      case 10:
        return "select(" + random_formula(depth - 1) + " >= 0, " + random_formula(depth - 1) +
               ", " + random_formula(depth - 1) + ")";
      case 11: return "copysign(" + random_formula(depth - 1) + ", " + v + " - 0.1)";
      case 12: return "(" + random_formula(depth - 1) + ")^3";
      default: return "sqrt(abs(" + random_formula(depth - 1) + "))";
    }
  };
  int finite = 0;
  const int cases = 3 * static_cast<int>(references.size());
  for (int k = 0; k < cases; ++k) {
    const auto& [ref_text, domain] = references[static_cast<std::size_t>(k) % references.size()];
    const ReferenceFunction f = make_reference(ref_text, domain);
    vars = variables_of(f);
    const std::string text = random_formula(3);
    const Expression e = formula(text, f);
    CertifyOptions o;
    o.time_limit_s = 0.1;
    const Certificate c = certify(e, vars, f, o);
    if (std::isfinite(c.bound)) ++finite;
    std::vector<double> x(f.domain.size());
    for (int i = 0; i < 100000 && std::isfinite(c.bound); ++i) {
      for (std::size_t j = 0; j < x.size(); ++j) {
        x[j] = f.domain[j].lo + f.domain[j].width() * unit(rng);
      }
      const double r = f.target_at(x);
      const double err = std::abs(eval_double(e, x) - r);
      ASSERT_TRUE(std::isfinite(err)) << text << " vs " << ref_text << " at x = " << x[0];
      ASSERT_LE(err, c.bound * (1 + 1e-12) + 1e-12 * (1 + std::abs(r)))
          << text << " vs " << ref_text << " at " << x[0] << ", " << x.back() << ": bound "
          << c.bound;
    }
  }
  EXPECT_GE(finite, cases * 2 / 3);
}

// The interval functions one by one: at random points of random boxes, the double value (to a
// few ulps) lies in the box's enclosure and in its mean-value form.
TEST(CertifyInterval, FunctionsEncloseTheirValues) {
  using verify::Dual;
  struct Unary {
    const char* name;
    Dual (*f)(const Dual&);
    double (*g)(double);
    double lo, hi;
  };
  const Unary unary[] = {
      {"sqrt", verify::sqrt, [](double x) { return std::sqrt(x); }, 0, 4},
      {"cbrt", verify::cbrt, [](double x) { return std::cbrt(x); }, -3, 3},
      {"exp", verify::exp, [](double x) { return std::exp(x); }, -3, 3},
      {"exp2", verify::exp2, [](double x) { return std::exp2(x); }, -3, 3},
      {"expm1", verify::expm1, [](double x) { return std::expm1(x); }, -3, 3},
      {"log", verify::log, [](double x) { return std::log(x); }, 0.01, 5},
      {"log2", verify::log2, [](double x) { return std::log2(x); }, 0.01, 5},
      {"log10", verify::log10, [](double x) { return std::log10(x); }, 0.01, 5},
      {"log1p", verify::log1p, [](double x) { return std::log1p(x); }, -0.99, 5},
      {"sin", verify::sin, [](double x) { return std::sin(x); }, -7, 7},
      {"cos", verify::cos, [](double x) { return std::cos(x); }, -7, 7},
      {"tan", verify::tan, [](double x) { return std::tan(x); }, -1.5, 1.5},
      {"asin", verify::asin, [](double x) { return std::asin(x); }, -1, 1},
      {"acos", verify::acos, [](double x) { return std::acos(x); }, -1, 1},
      {"atan", verify::atan, [](double x) { return std::atan(x); }, -5, 5},
      {"sinh", verify::sinh, [](double x) { return std::sinh(x); }, -3, 3},
      {"cosh", verify::cosh, [](double x) { return std::cosh(x); }, -3, 3},
      {"tanh", verify::tanh, [](double x) { return std::tanh(x); }, -3, 3},
      {"asinh", verify::asinh, [](double x) { return std::asinh(x); }, -3, 3},
      {"acosh", verify::acosh, [](double x) { return std::acosh(x); }, 1, 5},
      {"atanh", verify::atanh, [](double x) { return std::atanh(x); }, -0.99, 0.99},
      {"erf", verify::erf, [](double x) { return std::erf(x); }, -3, 3},
      {"erfc", verify::erfc, [](double x) { return std::erfc(x); }, -3, 3},
      {"abs", verify::abs, [](double x) { return std::abs(x); }, -2, 2},
      {"floor", verify::floor, [](double x) { return std::floor(x); }, -3, 3},
      {"round", verify::round, [](double x) { return std::round(x); }, -3, 3},
      {"saturate", verify::saturate, [](double x) { return apply_unary(Op::Saturate, x); }, -1, 2},
      {"sign", verify::sign, [](double x) { return apply_unary(Op::Sign, x); }, -1, 1},
  };
  struct Binary {
    const char* name;
    Dual (*f)(const Dual&, const Dual&);
    double (*g)(double, double);
    double lo, hi, lo2, hi2;
  };
  const Binary binary[] = {
      {"pow", verify::pow, [](double a, double b) { return std::pow(a, b); }, 0, 3, -2, 2},
      {"gpu_pow", verify::gpu_pow, [](double a, double b) { return apply_binary(Op::Pow, a, b); },
       0.1, 3, -2, 2},
      {"atan2", verify::atan2, [](double a, double b) { return std::atan2(a, b); }, -2, 2, -2, 2},
      {"hypot", verify::hypot, [](double a, double b) { return std::hypot(a, b); }, -2, 2, -2, 2},
      {"fmod", verify::fmod, [](double a, double b) { return std::fmod(a, b); }, -3, 3, 0.3, 2},
      {"fmin", verify::fmin, [](double a, double b) { return std::fmin(a, b); }, -2, 2, -2, 2},
      {"copysign", verify::copysign, [](double a, double b) { return std::copysign(a, b); }, -2, 2,
       -2, 2},
      {"div", [](const Dual& a, const Dual& b) { return a / b; },
       [](double a, double b) { return a / b; }, -2, 2, 0.5, 2},
      {"mul", [](const Dual& a, const Dual& b) { return a * b; },
       [](double a, double b) { return a * b; }, -2, 2, -2, 2},
  };
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(0, 1);
  verify::Arena arena(64, 2);
  verify::ArenaScope scope(arena);
  // Whether v (to a few ulps) is in the cell's value, or, with the gradient, in the mean-value
  // form around the point evaluation `at_mid` at `mid`.
  auto contains_interval = [](mpfi_srcptr c, double v) {
    const double slack = 8 * std::numeric_limits<double>::epsilon() * std::abs(v) + 1e-300;
    return mpfr_cmp_d(&c->left, v + slack) <= 0 && mpfr_cmp_d(&c->right, v - slack) >= 0;
  };
  auto contains = [&](const verify::Cell& c, double v) { return contains_interval(&c.v, v); };
  for (int trial = 0; trial < 300; ++trial) {
    for (const Unary& u : unary) {
      double a = u.lo + (u.hi - u.lo) * unit(rng), b = u.lo + (u.hi - u.lo) * unit(rng);
      if (trial % 3 == 0) b = a + (b - a) * 1e-3;  // narrow boxes too
      if (a > b) std::swap(a, b);
      const double lo[] = {a, 0}, hi[] = {b, 0};
      arena.begin(lo, hi, true);
      const Dual box = u.f(Dual::variable(0));
      ASSERT_FALSE(box->undefined()) << u.name << " on [" << a << ", " << b << "]";
      const double mid = a + 0.5 * (b - a);
      // The box's points: its midpoint, then its corners (a, 0), (b, 0), (a, 0), (b, 0).
      if (!box->constant) {
        ASSERT_TRUE(contains_interval(&box->p[0], u.g(mid))) << u.name << " at " << mid;
        ASSERT_TRUE(contains_interval(&box->p[1], u.g(a))) << u.name << " at " << a;
        ASSERT_TRUE(contains_interval(&box->p[2], u.g(b))) << u.name << " at " << b;
      }
      for (int k = 0; k < 8; ++k) {
        const double x = k == 0 ? a : (k == 1 ? b : a + (b - a) * unit(rng));
        const double v = u.g(x);
        ASSERT_TRUE(contains(*box, v)) << u.name << "(" << x << ") on [" << a << ", " << b << "]";
        if (!box->smooth || box->constant) continue;
        // The mean-value form: g(mid) + d * (x - mid) holds g(x).
        mpfi_t mv, t;
        mpfi_init2(mv, 64);
        mpfi_init2(t, 64);
        mpfi_set_d(mv, u.g(mid));
        mpfi_set_d(t, x);
        mpfi_sub_d(t, t, mid);
        mpfi_mul(t, t, &box->d[0]);
        mpfi_add(mv, mv, t);
        const double slack = 1e-14 * (1 + std::abs(v));
        EXPECT_TRUE(mpfr_cmp_d(&mv->left, v + slack) <= 0 && mpfr_cmp_d(&mv->right, v - slack) >= 0)
            << u.name << " mean value at " << x << " on [" << a << ", " << b << "]";
        // The second-order Taylor form: g(mid) + g'(mid) (x - mid) + h (x - mid)^2 / 2.
        if (box->smooth && box->taylor) {
          mpfi_t tf, q;
          mpfi_init2(tf, 64);
          mpfi_init2(q, 64);
          mpfi_set_d(tf, u.g(mid));
          mpfi_set_d(q, x);
          mpfi_sub_d(q, q, mid);
          mpfi_mul(t, q, &box->g[0]);
          mpfi_add(tf, tf, t);
          mpfi_sqr(q, q);
          mpfi_mul(q, q, &box->h[0]);
          mpfi_div_2ui(q, q, 1);
          mpfi_add(tf, tf, q);
          EXPECT_TRUE(mpfr_cmp_d(&tf->left, v + slack) <= 0 &&
                      mpfr_cmp_d(&tf->right, v - slack) >= 0)
              << u.name << " Taylor form at " << x << " on [" << a << ", " << b << "]";
          mpfi_clear(tf);
          mpfi_clear(q);
        }
        mpfi_clear(mv);
        mpfi_clear(t);
      }
    }
    for (const Binary& f : binary) {
      double a0 = f.lo + (f.hi - f.lo) * unit(rng), a1 = f.lo + (f.hi - f.lo) * unit(rng);
      double b0 = f.lo2 + (f.hi2 - f.lo2) * unit(rng), b1 = f.lo2 + (f.hi2 - f.lo2) * unit(rng);
      if (a0 > a1) std::swap(a0, a1);
      if (b0 > b1) std::swap(b0, b1);
      const double lo[] = {a0, b0}, hi[] = {a1, b1};
      arena.begin(lo, hi, true);
      const Dual box = f.f(Dual::variable(0), Dual::variable(1));
      for (int k = 0; k < 8; ++k) {
        const double x = a0 + (a1 - a0) * unit(rng), y = b0 + (b1 - b0) * unit(rng);
        const double v = f.g(x, y);
        if (std::isnan(v)) {
          EXPECT_TRUE(box->undefined()) << f.name << "(" << x << ", " << y << ") is NaN";
          continue;
        }
        if (box->undefined()) continue;
        ASSERT_TRUE(contains(*box, v)) << f.name << "(" << x << ", " << y << ") on [" << a0 << ", "
                                       << a1 << "] x [" << b0 << ", " << b1 << "]";
        if (!box->smooth || !box->taylor || box->constant) continue;
        // f(m) + g . o + o' H o / 2 with o = (x, y) - m, m the midpoint.
        const double m[] = {a0 + 0.5 * (a1 - a0), b0 + 0.5 * (b1 - b0)};
        const double o[] = {x - m[0], y - m[1]};
        mpfi_t tf, q;
        mpfi_init2(tf, 64);
        mpfi_init2(q, 64);
        mpfi_set_d(tf, f.g(m[0], m[1]));
        for (int i = 0; i < 2; ++i) {
          mpfi_mul_d(q, &box->g[i], o[i]);
          mpfi_add(tf, tf, q);
          for (int j = i; j < 2; ++j) {
            mpfi_mul_d(q, &box->h[verify::hessian_index(i, j)], o[i] * o[j] * (i == j ? 0.5 : 1));
            mpfi_add(tf, tf, q);
          }
        }
        const double slack = 1e-13 * (1 + std::abs(v));
        EXPECT_TRUE(mpfr_cmp_d(&tf->left, v + slack) <= 0 && mpfr_cmp_d(&tf->right, v - slack) >= 0)
            << f.name << " Taylor form at (" << x << ", " << y << ")";
        mpfi_clear(tf);
        mpfi_clear(q);
      }
    }
  }
}

TEST(CertifyInterval, SquareOfOneHandleIsTight) {
  using verify::Dual;
  verify::Arena arena(64, 1);
  verify::ArenaScope scope(arena);
  const double lo[] = {-1}, hi[] = {2};
  arena.begin(lo, hi, true);
  const Dual x = Dual::variable(0);
  const Dual sq = x * x;
  EXPECT_EQ(mpfr_cmp_d(&sq->v.left, 0), 0);
  EXPECT_EQ(mpfr_cmp_d(&sq->v.right, 4), 0);
  const Dual cube = verify::ipow(x, 3);
  EXPECT_EQ(mpfr_cmp_d(&cube->v.left, -1), 0);
  EXPECT_EQ(mpfr_cmp_d(&cube->v.right, 8), 0);
  // abs straddling 0: value [0, 2], slopes [-1, 1].
  const Dual a = verify::abs(x);
  EXPECT_TRUE(a->smooth);
  EXPECT_EQ(mpfr_cmp_d(&a->d[0].left, -1), 0);
  EXPECT_EQ(mpfr_cmp_d(&a->d[0].right, 1), 0);
  // An undecided select is a jump: not smooth.
  const Dual s = verify::select(x, Dual(1.0), Dual(-1.0));
  EXPECT_FALSE(s->smooth);
  EXPECT_EQ(mpfr_cmp_d(&s->v.left, -1), 0);
  // Division by an interval holding 0: unbounded, and undefined where 0 / 0 may occur.
  const Dual q = Dual(1.0) / x;
  EXPECT_FALSE(mpfi_bounded_p(&q->v));
  EXPECT_FALSE(q->undefined());
  EXPECT_TRUE((x / x)->undefined());
}

}  // namespace
}  // namespace shaderfit
