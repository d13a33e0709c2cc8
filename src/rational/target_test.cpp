#include "shaderfit/rational/target.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "shaderfit/core/error.hpp"
#include "shaderfit/expr/jet.hpp"
#include "shaderfit/reference/fresnel.hpp"
#include "shaderfit/reference/smith_ggx.hpp"

namespace shaderfit::rational {
namespace {

TEST(RationalTarget, BuiltinsMatchTheReferenceFunctions) {
  const std::vector<double> ior = {1.5};
  const Target f = Target::builtin("fresnel-dielectric");
  EXPECT_EQ(f.variable(), "cos");
  for (double c : {0.0, 0.3, 0.7, 1.0})
    EXPECT_DOUBLE_EQ(f.value(c, ior), reference::fresnel_dielectric(c, 1.5));
  const Target f0 = Target::builtin("fresnel-dielectric-f0");
  const std::vector<double> r0 = {0.04};
  EXPECT_NEAR(f0.value(1.0, r0), 0.04, 1e-15);
  EXPECT_NEAR(f0.value(0.4, r0), reference::fresnel_dielectric(0.4, 1.5), 1e-14);
  const Target g = Target::builtin("smith-ggx-g1");
  const std::vector<double> alpha = {0.3};
  for (double v : {0.05, 0.5, 1.0})
    EXPECT_NEAR(g.value(v, alpha), reference::smith_ggx_g1(v, 0.3), 1e-15);
}

TEST(RationalTarget, DerivativesOfEveryOrderAreExact) {
  const Target e = Target::builtin("exp");
  const std::vector<double> d = e.derivatives(0.5, 12, {});
  for (double v : d) EXPECT_NEAR(v, std::exp(0.5), 1e-13);
  // Schlick's Fresnel: F^(k)(1) = 0 for k = 1..4, F^(5)(1) = -120 (1 - F0).
  const Target s = Target::builtin("fresnel-schlick");
  const std::vector<double> p = {0.25};
  const std::vector<double> ds = s.derivatives(1.0, 6, p);
  EXPECT_NEAR(ds[0], 0.25, 1e-15);
  for (int k = 1; k <= 4; ++k) EXPECT_NEAR(ds[k], 0.0, 1e-12) << k;
  EXPECT_NEAR(ds[5], -120 * 0.75, 1e-10);
  EXPECT_NEAR(ds[6], 0.0, 1e-10);
  // atan' = 1 / (1 + x^2), atan'' = -2x / (1 + x^2)^2, atan''' = (6x^2 - 2) / (1 + x^2)^3.
  const std::vector<double> da = Target::builtin("atan").derivatives(0.5, 3, {});
  EXPECT_NEAR(da[1], 1 / 1.25, 1e-15);
  EXPECT_NEAR(da[2], -1.0 / (1.25 * 1.25), 1e-15);
  EXPECT_NEAR(da[3], (6 * 0.25 - 2) / (1.25 * 1.25 * 1.25), 1e-14);
  // Smith GGX G1'(0) = 2 / alpha.
  EXPECT_NEAR(Target::builtin("smith-ggx-g1").derivatives(0.0, 1, std::vector<double>{0.4})[1], 5.0,
              1e-13);
}

TEST(RationalTarget, FormulaTargetsAgreeWithBuiltins) {
  const Target f = Target::formula("F0 + (1 - F0) * (1 - x)^5", "x", {"F0"});
  const Target b = Target::builtin("fresnel-schlick");
  const std::vector<double> p = {0.1};
  for (double x : {0.0, 0.2, 0.9}) EXPECT_NEAR(f.value(x, p), b.value(x, p), 1e-15);
  const auto df = f.derivatives(0.3, 7, p), db = b.derivatives(0.3, 7, p);
  for (int k = 0; k <= 7; ++k) EXPECT_NEAR(df[k], db[k], 1e-11) << k;
  const Target t = Target::formula("sin(x) * exp2(x) / sqrt(1 + x^2)", "x", {});
  // Against a central difference.
  const double h = 1e-5, x = 0.7;
  const double fd = (t.value(x + h, {}) - t.value(x - h, {})) / (2 * h);
  EXPECT_NEAR(t.derivatives(x, 1, {})[1], fd, 1e-9);
}

TEST(RationalTarget, IntegralsByGaussLegendre) {
  EXPECT_NEAR(Target::builtin("exp").integral(-1, 1, {}), std::exp(1.0) - std::exp(-1.0), 1e-14);
  EXPECT_NEAR(Target::builtin("fresnel-schlick").integral(0, 1, std::vector<double>{0.04}),
              0.04 + 0.96 / 6, 1e-15);
  EXPECT_NEAR(Target::formula("abs(x - 0.3)", "x", {}).integral(0, 1, {}), (0.09 + 0.49) / 2,
              1e-12);
}

TEST(RationalTarget, UnknownNamesAndBadFormulas) {
  EXPECT_THROW((void)Target::builtin("fresnel"), Error);
  try {
    (void)Target::formula("x + * 2", "x", {});
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.where().source, "RationalProblem::target");
    EXPECT_GT(e.where().column, 0);
  }
}

}  // namespace
}  // namespace shaderfit::rational
