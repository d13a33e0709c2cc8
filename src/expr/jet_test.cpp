// Taylor jets of the functions the reference language adds (expr/jet.hpp): each against its known
// series, its inverse, or finite differences of the double function.
#include "shaderfit/expr/jet.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>

namespace shaderfit {
namespace {

constexpr int kOrder = 10;

// The first derivative by a central difference of f (h scaled to x), to compare with c_1.
double central(const std::function<double(double)>& f, double x) {
  const double h = 1e-6 * std::max(1.0, std::abs(x));
  return (f(x + h) - f(x - h)) / (2 * h);
}

// The second derivative likewise, for 2 c_2.
double central2(const std::function<double(double)>& f, double x) {
  const double h = 1e-4 * std::max(1.0, std::abs(x));
  return (f(x + h) - 2 * f(x) + f(x - h)) / (h * h);
}

struct Case {
  const char* name;
  std::function<Jet(const Jet&)> jet;
  std::function<double(double)> f;
  std::vector<double> at;
};

TEST(Jet, ValuesAndFirstTwoDerivativesMatchTheDoubleFunctions) {
  const std::vector<Case> cases = {
      {"tan",
       [](const Jet& a) { return tan(a); },
       [](double x) { return std::tan(x); },
       {-1.2, 0.3, 1.0}},
      {"asin",
       [](const Jet& a) { return asin(a); },
       [](double x) { return std::asin(x); },
       {-0.9, 0.1, 0.7}},
      {"acos",
       [](const Jet& a) { return acos(a); },
       [](double x) { return std::acos(x); },
       {-0.9, 0.1, 0.7}},
      {"sinh",
       [](const Jet& a) { return sinh(a); },
       [](double x) { return std::sinh(x); },
       {-2.0, 0.5, 3.0}},
      {"cosh",
       [](const Jet& a) { return cosh(a); },
       [](double x) { return std::cosh(x); },
       {-2.0, 0.5, 3.0}},
      {"tanh",
       [](const Jet& a) { return tanh(a); },
       [](double x) { return std::tanh(x); },
       {-2.0, 0.5, 3.0}},
      {"asinh",
       [](const Jet& a) { return asinh(a); },
       [](double x) { return std::asinh(x); },
       {-2.0, 0.5, 3.0}},
      {"acosh",
       [](const Jet& a) { return acosh(a); },
       [](double x) { return std::acosh(x); },
       {1.5, 2.0, 7.0}},
      {"atanh",
       [](const Jet& a) { return atanh(a); },
       [](double x) { return std::atanh(x); },
       {-0.8, 0.1, 0.6}},
      {"erf",
       [](const Jet& a) { return erf(a); },
       [](double x) { return std::erf(x); },
       {-1.5, 0.2, 2.0}},
      {"erfc",
       [](const Jet& a) { return erfc(a); },
       [](double x) { return std::erfc(x); },
       {-1.5, 0.2, 2.0}},
      {"cbrt",
       [](const Jet& a) { return cbrt(a); },
       [](double x) { return std::cbrt(x); },
       {-8.0, 0.3, 5.0}},
      {"expm1",
       [](const Jet& a) { return expm1(a); },
       [](double x) { return std::expm1(x); },
       {-1.0, 1e-3, 2.0}},
      {"log1p",
       [](const Jet& a) { return log1p(a); },
       [](double x) { return std::log1p(x); },
       {-0.5, 1e-3, 4.0}},
      {"log10",
       [](const Jet& a) { return log10(a); },
       [](double x) { return std::log10(x); },
       {0.2, 1.0, 300.0}},
      {"exp2",
       [](const Jet& a) { return exp2(a); },
       [](double x) { return std::exp2(x); },
       {-3.0, 0.5, 4.0}},
      {"log2",
       [](const Jet& a) { return log2(a); },
       [](double x) { return std::log2(x); },
       {0.3, 1.0, 9.0}},
      {"pow(x, 2.4)",
       [](const Jet& a) { return pow(a, Jet(2.4)); },
       [](double x) { return std::pow(x, 2.4); },
       {0.2, 1.0, 3.0}},
      {"pow(x, 3) at x < 0",
       [](const Jet& a) { return pow(a, Jet(3.0)); },
       [](double x) { return std::pow(x, 3.0); },
       {-2.0, -0.5}},
      {"pow(2, x)",
       [](const Jet& a) { return pow(Jet(2.0), a); },
       [](double x) { return std::pow(2.0, x); },
       {-1.0, 0.5, 3.0}},
      {"atan2(x, 0.7)",
       [](const Jet& a) { return atan2(a, Jet(0.7)); },
       [](double x) { return std::atan2(x, 0.7); },
       {-2.0, 0.1, 3.0}},
      {"atan2(0.7, x)",
       [](const Jet& a) { return atan2(Jet(0.7), a); },
       [](double x) { return std::atan2(0.7, x); },
       {-2.0, 0.1, 3.0}},
      {"atan2(-0.3, x) in the third quadrant",
       [](const Jet& a) { return atan2(Jet(-0.3), a); },
       [](double x) { return std::atan2(-0.3, x); },
       {-2.0, -0.5}},
      {"hypot(x, 1.5)",
       [](const Jet& a) { return hypot(a, Jet(1.5)); },
       [](double x) { return std::hypot(x, 1.5); },
       {-2.0, 0.1, 3.0}},
      {"hypot(x, x) far beyond sqrt(max double)",
       [](const Jet& a) { return hypot(a, a); },
       [](double x) { return std::hypot(x, x); },
       {1e300}},
      {"fmod(x, 0.75)",
       [](const Jet& a) { return fmod(a, Jet(0.75)); },
       [](double x) { return std::fmod(x, 0.75); },
       {-2.0, 0.1, 3.1}},
      {"fmod(2.5, x)",
       [](const Jet& a) { return fmod(Jet(2.5), a); },
       [](double x) { return std::fmod(2.5, x); },
       {0.7, 1.1, -0.9}},
      {"floor",
       [](const Jet& a) { return floor(a); },
       [](double x) { return std::floor(x); },
       {-1.5, 0.3}},
      {"ceil",
       [](const Jet& a) { return ceil(a); },
       [](double x) { return std::ceil(x); },
       {-1.5, 0.3}},
      {"trunc",
       [](const Jet& a) { return trunc(a); },
       [](double x) { return std::trunc(x); },
       {-1.5, 0.3}},
      {"round",
       [](const Jet& a) { return round(a); },
       [](double x) { return std::round(x); },
       {-1.3, 0.3}},
  };
  for (const Case& c : cases) {
    for (const double x : c.at) {
      const Jet j = c.jet(Jet::variable(x, kOrder));
      const double scale = std::max(1.0, std::abs(c.f(x)));
      EXPECT_EQ(j.value(), c.f(x)) << c.name << " at " << x;
      EXPECT_NEAR(j.derivative(1), central(c.f, x), 1e-6 * scale) << c.name << " at " << x;
      EXPECT_NEAR(j.derivative(2), central2(c.f, x), 1e-3 * scale) << c.name << " at " << x;
    }
  }
}

// Every order at once: functions composed with their inverses give the identity's jet.
TEST(Jet, InversesComposeToTheIdentityAtEveryOrder) {
  const std::vector<std::pair<const char*, std::function<Jet(const Jet&)>>> identities = {
      {"asin(sin)", [](const Jet& a) { return asin(sin(a)); }},
      {"acos(cos)", [](const Jet& a) { return acos(cos(a)); }},
      {"atan(tan)", [](const Jet& a) { return atan(tan(a)); }},
      {"asinh(sinh)", [](const Jet& a) { return asinh(sinh(a)); }},
      {"acosh(cosh)", [](const Jet& a) { return acosh(cosh(a)); }},
      {"atanh(tanh)", [](const Jet& a) { return atanh(tanh(a)); }},
      {"log1p(expm1)", [](const Jet& a) { return log1p(expm1(a)); }},
      {"log10(10^x)", [](const Jet& a) { return log10(pow(Jet(10.0), a)); }},
      {"cbrt(x^3)", [](const Jet& a) { return cbrt(a * a * a); }},
      {"pow(pow(x, 2.5), 0.4)", [](const Jet& a) { return pow(pow(a, Jet(2.5)), Jet(0.4)); }},
      {"atan2(sin, cos)", [](const Jet& a) { return atan2(sin(a), cos(a)); }},
      {"hypot(3x, 4x) / 5",
       [](const Jet& a) { return hypot(Jet(3.0) * a, Jet(4.0) * a) / Jet(5.0); }},
      {"erf + erfc - 1 + x", [](const Jet& a) { return erf(a) + erfc(a) - Jet(1.0) + a; }},
  };
  for (const auto& [name, f] : identities) {
    for (const double x : {0.3, 0.7, 1.1}) {
      const Jet j = f(Jet::variable(x, kOrder));
      EXPECT_NEAR(j.c[0], x, 1e-14) << name << " at " << x;
      EXPECT_NEAR(j.c[1], 1.0, 1e-13) << name << " at " << x;
      for (int k = 2; k <= kOrder; ++k) EXPECT_NEAR(j.c[k], 0.0, 1e-9) << name << " order " << k;
    }
  }
}

// Known Maclaurin coefficients.
TEST(Jet, SeriesAtZeroAreTheKnownOnes) {
  const Jet x = Jet::variable(0.0, 9);
  const double tan_c[] = {0, 1, 0, 1.0 / 3, 0, 2.0 / 15, 0, 17.0 / 315, 0, 62.0 / 2835};
  const double tanh_c[] = {0, 1, 0, -1.0 / 3, 0, 2.0 / 15, 0, -17.0 / 315, 0, 62.0 / 2835};
  const double k = 2 / std::sqrt(std::numbers::pi);
  const double erf_c[] = {0, k, 0, -k / 3, 0, k / 10, 0, -k / 42, 0, k / 216};
  const double asin_c[] = {0, 1, 0, 1.0 / 6, 0, 3.0 / 40, 0, 5.0 / 112, 0, 35.0 / 1152};
  const Jet t = tan(x), th = tanh(x), e = erf(x), as = asin(x);
  for (int i = 0; i <= 9; ++i) {
    EXPECT_NEAR(t.c[i], tan_c[i], 1e-15) << "tan " << i;
    EXPECT_NEAR(th.c[i], tanh_c[i], 1e-15) << "tanh " << i;
    EXPECT_NEAR(e.c[i], erf_c[i], 1e-15) << "erf " << i;
    EXPECT_NEAR(as.c[i], asin_c[i], 1e-15) << "asin " << i;
  }
}

TEST(Jet, StepsHaveNoDerivativesAndMinMaxSkipNaN) {
  const Jet x = Jet::variable(2.5, 3);
  EXPECT_EQ(floor(x).derivative(1), 0.0);
  EXPECT_EQ(round(x).value(), 3.0);
  EXPECT_EQ(fmod(x, Jet(1.0)).derivative(1), 1.0);
  EXPECT_EQ(fmod(Jet(7.0), x).derivative(1), -2.0);  // -trunc(7 / 2.5)
  const Jet nan(std::nan(""));
  EXPECT_EQ(fmin(nan, x).value(), 2.5);
  EXPECT_EQ(fmax(nan, x).derivative(1), 1.0);
  EXPECT_EQ(fmin(x, nan).value(), 2.5);
}

// The value is the double function's, down to the sign of a zero.
TEST(Jet, ZerosKeepTheirSign) {
  const Jet negative_zero = Jet::variable(-0.0, 2);
  EXPECT_FALSE(std::signbit(abs(negative_zero).value()));
  EXPECT_TRUE(std::signbit((negative_zero * Jet(0.0)).value()));
  EXPECT_TRUE(std::signbit((Jet(0.0) * negative_zero).value()));
  EXPECT_TRUE(std::signbit(sqrt(negative_zero).value()));
}

}  // namespace
}  // namespace shaderfit
