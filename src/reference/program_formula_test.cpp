#include "shaderfit/reference/program_formula.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "expr/random_expression_test_util.hpp"
#include "shaderfit/expr/print.hpp"
#include "shaderfit/reference/language.hpp"

namespace shaderfit::reference {
namespace {

Program shader(const std::string& source, const std::string& function) {
  ReferenceText t;
  t.shader_source = source;
  t.shader_path = "test.glsl";
  t.function = function;
  return compile_reference(t);
}

Program formula(const std::string& text, std::vector<std::string> variables) {
  ReferenceText t;
  t.formula = text;
  t.variables = std::move(variables);
  return compile_reference(t);
}

// The formula's value at `x` (one value per variable), by op.hpp's meaning.
double value(const Expression& e, const std::vector<double>& x) {
  return testing::eval_reference(e, x);
}

// The formula means the program on random points of [lo, hi]^n.
void expect_same_function(const Program& p, const Expression& e, double lo, double hi) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(lo, hi);
  for (int i = 0; i < 500; ++i) {
    std::vector<double> x(p.inputs.size());
    for (double& v : x) v = u(rng);
    const double want = p.evaluate(x);
    EXPECT_NEAR(value(e, x), want, 1e-12 * (1 + std::fabs(want))) << x[0];
  }
}

constexpr const char* kBurley = R"(
float F_Schlick90(float f90, float u)
{
    float m = saturate(1.0 - u);
    float m2 = m * m;
    return 1.0 + (f90 - 1.0) * m2 * m2 * m;
}
float Fd_Burley(float NoV, float NoL, float LoH, float roughness)
{
    float f90 = 0.5 + 2.0 * roughness * LoH * LoH;
    return F_Schlick90(f90, NoL) * F_Schlick90(f90, NoV) * (1.0 / 3.14159265);
}
)";

TEST(ProgramFormula, ShaderFunctionsWithHelpersAndClampsAreWrittenOut) {
  const Program burley = shader(kBurley, "Fd_Burley");
  const std::vector<std::string> vars = {"NoV", "NoL", "LoH", "roughness"};
  const ProgramFormula f = program_formula(burley, vars);
  ASSERT_TRUE(f.formula) << f.why;
  EXPECT_EQ(f.formula->variables, vars);
  expect_same_function(burley, *f.formula, 0, 1);

  const Program hg = shader(R"(
#define PI 3.14159265
float phaseHG(float cosTheta, float g) {
  float g2 = g * g;
  float invLen = inversesqrt(max(1.0 + g2 - 2.0 * g * cosTheta, 1e-6));
  return (1.0 - g2) * invLen * invLen * invLen / (4.0 * PI);
})",
                            "phaseHG");
  const ProgramFormula h = program_formula(hg, std::vector<std::string>{"cosTheta", "g"});
  ASSERT_TRUE(h.formula) << h.why;
  expect_same_function(hg, *h.formula, -0.9, 0.9);
}

TEST(ProgramFormula, AClampToZeroOneIsSaturate) {
  for (const char* text : {"clamp(x, 0.0, 1.0) * 2.0", "saturate(x) * 2.0",
                           "min(max(x, 0.0), 1.0) * 2.0", "min(1.0, max(0.0, x)) * 2.0"}) {
    const Program p = shader(std::string("float f(float x) { return ") + text + "; }", "f");
    const ProgramFormula f = program_formula(p, std::vector<std::string>{"x"});
    ASSERT_TRUE(f.formula) << f.why;
    ASSERT_EQ(f.formula->size(), 4u) << text;  // x saturate 2 *
    EXPECT_EQ(f.formula->nodes[1].op, Op::Saturate) << text;
    expect_same_function(p, *f.formula, -2, 2);
  }
}

TEST(ProgramFormula, VariablesMayComeInAnotherOrder) {
  const Program p = formula("x - 2 * y^3", {"x", "y"});
  const ProgramFormula f = program_formula(p, std::vector<std::string>{"y", "z", "x"});
  ASSERT_TRUE(f.formula) << f.why;
  EXPECT_NEAR(value(*f.formula, {2.0, 0.0, 5.0}), 5 - 16, 1e-15);
}

TEST(ProgramFormula, BranchesOnComparisonsAreSelects) {
  const Program p = shader(R"(
float f(float x, float y) {
  if (x < 0.25) return x * y;
  float z = y > x ? exp(y) : log(x + 1.0);
  return x >= 0.5 ? z : (y <= 0.0 ? -z : z * 2.0);
})",
                           "f");
  const ProgramFormula f = program_formula(p, std::vector<std::string>{"x", "y"});
  ASSERT_TRUE(f.formula) << f.why;
  expect_same_function(p, *f.formula, -1, 1);
}

TEST(ProgramFormula, PowersBeyondTheOperatorsRangeArePow) {
  const Program p = formula("x^20 + x^-3 + x^0 + pow(x, 1)", {"x"});
  const ProgramFormula f = program_formula(p, std::vector<std::string>{"x"});
  ASSERT_TRUE(f.formula) << f.why;
  expect_same_function(p, *f.formula, 0.5, 1.5);
}

TEST(ProgramFormula, WhatTheOperatorsCannotWriteIsSaid) {
  const auto why = [](const std::string& text, std::vector<std::string> vars) {
    const ProgramFormula f = program_formula(formula(text, vars), vars);
    EXPECT_FALSE(f.formula) << text;
    return f.why;
  };
  EXPECT_EQ(why("floor(x) + 1", {"x"}),
            "it calls floor (or fract, frac or mod), which the search's operators cannot "
            "write");
  EXPECT_EQ(why("(x < y) * 2", {"x", "y"}),
            "it reads '<' as a number, which the search's operators cannot write");
  EXPECT_EQ(why("fresnel_exact(x, 1.5, 0)", {"x"}), "it calls a built-in reference");
  const ProgramFormula missing =
      program_formula(formula("x + y", {"x", "y"}), std::vector<std::string>{"x"});
  EXPECT_FALSE(missing.formula);
  EXPECT_EQ(missing.why, "its input 'y' is not a variable of the formula");
}

TEST(ProgramFormula, EqualityBranchesAreSelectsOnTheDifference) {
  const Program p = shader(R"(
float f(float x, float y) {
  if (x == 0.5) return 2.0;
  return x != y ? x * y : 3.0;
})",
                           "f");
  const ProgramFormula f = program_formula(p, std::vector<std::string>{"x", "y"});
  ASSERT_TRUE(f.formula) << f.why;
  for (const auto& [x, y] : {std::pair{0.5, 0.1}, {0.25, 0.25}, {0.3, 0.7}, {-1.0, -1.0}})
    EXPECT_DOUBLE_EQ(value(*f.formula, {x, y}), p.evaluate(std::vector<double>{x, y}))
        << x << ", " << y;
  EXPECT_EQ(to_infix(*f.formula),
            "select(-abs(x - 0.5) >= 0, 2, select(-abs(x - y) >= 0, 3, x * y))");
}

TEST(ProgramFormula, FunctionsTheOperatorsWriteExactlyAreWrittenInThem) {
  for (const char* text : {"tan(x)", "cbrt(x - 0.3)", "log10(x)", "log1p(x)", "expm1(x)",
                           "sinh(x)", "cosh(x)", "asinh(x - 0.5)", "acosh(x + 1)",
                           "atanh(x - 0.5)", "erfc(x)", "hypot(x, 2 * x + 1)"}) {
    const Program p = formula(text, {"x"});
    const ProgramFormula f = program_formula(p, std::vector<std::string>{"x"});
    ASSERT_TRUE(f.formula) << text << ": " << f.why;
    expect_same_function(p, *f.formula, 0.05, 0.95);
  }
}

TEST(ProgramFormula, AFormulaTooLargeToWriteOutIsSaid) {
  // Each line reads the one before twice: 2^14 leaves written out.
  std::string src = "float f(float x) {\n  float a0 = x;\n";
  for (int i = 1; i <= 14; ++i)
    src += "  float a" + std::to_string(i) + " = a" + std::to_string(i - 1) + " * a" +
           std::to_string(i - 1) + " + x;\n";
  src += "  return a14;\n}\n";
  const ProgramFormula f = program_formula(shader(src, "f"), std::vector<std::string>{"x"});
  EXPECT_FALSE(f.formula);
  EXPECT_NE(f.why.find("more than 4096 nodes"), std::string::npos) << f.why;
}

}  // namespace
}  // namespace shaderfit::reference
