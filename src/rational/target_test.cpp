#include "shaderfit/rational/target.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

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

TEST(RationalTarget, ReferenceLanguageFormulasHaveExactDerivatives) {
  const double rpi = 1 / std::sqrt(std::numbers::pi);
  const Target a = Target::formula("acos(x)", "x", {});
  const Target e = Target::formula("erf(x)", "x", {});
  const Target t = Target::formula("atan2(x, 1)", "x", {});
  for (double x : {-0.7, 0.0, 0.3, 0.9}) {
    EXPECT_EQ(a.value(x, {}), std::acos(x));
    const double s = 1 - x * x;
    const std::vector<double> da = a.derivatives(x, 3, {});
    EXPECT_NEAR(da[1], -1 / std::sqrt(s), 1e-14) << x;
    EXPECT_NEAR(da[2], -x / std::pow(s, 1.5), 1e-13) << x;
    EXPECT_NEAR(da[3], -(1 + 2 * x * x) / std::pow(s, 2.5), 1e-12) << x;
    const std::vector<double> de = e.derivatives(x, 3, {});
    EXPECT_EQ(de[0], std::erf(x));
    const double g = 2 * rpi * std::exp(-x * x);
    EXPECT_NEAR(de[1], g, 1e-15) << x;
    EXPECT_NEAR(de[2], -2 * x * g, 1e-15) << x;
    EXPECT_NEAR(de[3], (4 * x * x - 2) * g, 1e-14) << x;
    const std::vector<double> dt = t.derivatives(x, 4, {});
    const std::vector<double> datan = Target::builtin("atan").derivatives(x, 4, {});
    for (int k = 0; k <= 4; ++k) EXPECT_NEAR(dt[k], datan[k], 1e-13) << x << " " << k;
  }
  // Parameters are the other names; the built-in references by call.
  const Target f = Target::formula("fresnel_schlick(x, F0) - F0 * tanh(x)", "x", {"F0"});
  const std::vector<double> p = {0.04};
  const double x = 0.4;
  EXPECT_NEAR(f.value(x, p), 0.04 + 0.96 * std::pow(0.6, 5) - 0.04 * std::tanh(x), 1e-15);
  const double sech2 = 1 / (std::cosh(x) * std::cosh(x));
  EXPECT_NEAR(f.derivatives(x, 1, p)[1], -5 * 0.96 * std::pow(0.6, 4) - 0.04 * sech2, 1e-14);
  EXPECT_EQ(f.parameters(), (std::vector<std::string>{"F0"}));
}

TEST(RationalTarget, ShaderFunctions) {
  const std::string g1 =
      "float G1(float NdotV, float roughness) {\n"
      "  float a2 = roughness * roughness;\n"
      "  return 2.0 * NdotV / (NdotV + sqrt(a2 + (1.0 - a2) * NdotV * NdotV));\n"
      "}\n";
  // The variable: the parameter named so, or the one without a value.
  const Target by_name = Target::shader(g1, "g1.glsl", "G1", "NdotV", {});
  EXPECT_EQ(by_name.variable(), "NdotV");
  EXPECT_EQ(by_name.parameters(), (std::vector<std::string>{"roughness"}));
  EXPECT_EQ(by_name.name(), "g1.glsl: G1");
  const Target by_value = Target::shader(g1, "g1.glsl", "G1", "x", {"roughness", "k"});
  EXPECT_EQ(by_value.variable(), "NdotV");
  const std::vector<double> alpha = {0.4};
  const Target builtin = Target::builtin("smith-ggx-g1");
  for (double v : {0.1, 0.5, 1.0}) {
    EXPECT_NEAR(by_value.value(v, alpha), builtin.value(v, alpha), 1e-15) << v;
    const auto ds = by_value.derivatives(v, 3, alpha), db = builtin.derivatives(v, 3, alpha);
    for (int k = 0; k <= 3; ++k) EXPECT_NEAR(ds[k], db[k], 1e-11 * (1 + std::abs(db[k]))) << k;
  }
  try {
    (void)Target::shader(g1, "g1.glsl", "G1", "x", {}, "RationalSetup::variable");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.where().source, "RationalSetup::variable");
    EXPECT_NE(e.message().find("NdotV, roughness"), std::string::npos) << e.message();
  }
  try {
    (void)Target::shader("float f(float x) {\n  while (x > 1) x -= 1;\n  return x;\n}\n", "f.hlsl",
                         "f", "x", {});
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.where().source, "f.hlsl");
    EXPECT_EQ(e.where().line, 2);
  }
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
  try {
    (void)Target::formula("2 * acoss(x)", "x", {}, "RationalSetup::target");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.where().source, "RationalSetup::target");
    EXPECT_EQ(e.where().column, 5);
    EXPECT_NE(e.message().find("unknown function 'acoss'"), std::string::npos) << e.message();
  }
  try {
    (void)Target::formula("x + y", "x", {"F0"});
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(e.message().find("unknown variable 'y'"), std::string::npos) << e.message();
  }
}

}  // namespace
}  // namespace shaderfit::rational
