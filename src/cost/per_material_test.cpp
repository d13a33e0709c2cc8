#include "shaderfit/cost/per_material.hpp"

#include <gtest/gtest.h>

#include "shaderfit/cost/cost_model.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/expr/print.hpp"

namespace shaderfit {
namespace {

const std::vector<std::string> kAlpha = {"alpha"};

TEST(PerMaterial, BlinnPhongHoistsItsExponentAndScale) {
  const Expression e = parse_formula("1/(3.14159*alpha^2) * pow(NoH, 2/alpha^2 - 2)");
  const MaterialSplit s = split_per_material(e, kAlpha);
  ASSERT_EQ(s.values.size(), 2u);
  EXPECT_EQ(s.per_pixel.variables, (std::vector<std::string>{"NoH", "m0", "m1"}));
  EXPECT_EQ(instruction_count(s.per_pixel, InstructionTarget::Sass), 3);
  const SplitCost c = split_instruction_count(e, kAlpha, InstructionTarget::Sass);
  EXPECT_EQ(c.per_pixel, 3);
  EXPECT_EQ(c.per_material, material_instruction_cost(s, InstructionTarget::Sass).instructions);
  EXPECT_GT(c.per_material, 0);
  EXPECT_EQ(expression_cost(e, CostTarget::Instructions, kAlpha), 3.0);
  // Every pixel pays for it all without the uniform input.
  EXPECT_GT(expression_cost(e, CostTarget::Instructions), 6.0);
}

TEST(PerMaterial, NoUniformInputReadIsTheFormulaItself) {
  const Expression e = parse_formula("r0 + (x - r0)*x^4");
  const MaterialSplit s = split_per_material(e, kAlpha);
  EXPECT_TRUE(s.values.empty());
  EXPECT_EQ(s.per_pixel, e);
  EXPECT_EQ(split_instruction_count(e, kAlpha, InstructionTarget::Sass).per_pixel, 4);
}

TEST(PerMaterial, BareUniformInputsKeepTheirNamesAndEqualValuesAreOne) {
  const Expression e = parse_formula("alpha*x + (alpha^2 - 1)*x^2 + (alpha^2 - 1)");
  const MaterialSplit s = split_per_material(e, kAlpha);
  ASSERT_EQ(s.values.size(), 2u);
  EXPECT_EQ(s.values[0].name, "alpha");
  EXPECT_EQ(s.values[1].name, "m0");
  EXPECT_EQ(s.per_pixel.variables, (std::vector<std::string>{"x", "alpha", "m0"}));
  // alpha^2 - 1 is one FFMA per material, read twice per pixel.
  EXPECT_EQ(split_instruction_count(e, kAlpha, InstructionTarget::Sass).per_material, 1);
}

TEST(PerMaterial, TheExpRewriteNeedsANonNegativeValueAndAGain) {
  // alpha may be negative: exp2(x + log2 alpha) would be NaN there.
  const Expression signed_scale = parse_formula("alpha * exp2(x*x)");
  EXPECT_EQ(split_instruction_count(signed_scale, kAlpha, InstructionTarget::Sass).per_pixel, 3);
  const Expression square_scale = parse_formula("alpha^2 * exp2(x*x)");
  EXPECT_EQ(split_instruction_count(square_scale, kAlpha, InstructionTarget::Sass).per_pixel, 2);
  const Expression divided = parse_formula("exp(x*x) / (alpha^2 + 1)");
  EXPECT_EQ(split_instruction_count(divided, kAlpha, InstructionTarget::Sass).per_pixel, 3);
}

TEST(PerMaterial, ParametersStayWhereTheyAreRead) {
  Expression e = parse_formula("c0 * alpha + c1 * x",
                               {.variables = {"x", "alpha"}, .parameters = {"c0", "c1"}});
  e.parameter_values = {2.0, 3.0};
  const MaterialSplit s = split_per_material(e, kAlpha);
  EXPECT_EQ(s.per_pixel.parameters, (std::vector<std::string>{"c1"}));
  EXPECT_EQ(s.per_pixel.parameter_values, (std::vector<double>{3.0}));
  ASSERT_EQ(s.values.size(), 1u);
  EXPECT_EQ(s.values[0].value.parameters.size(), 2u);
}

TEST(PerMaterial, ValueNamesStepAroundInputsCalledSo) {
  const Expression e = parse_formula("m0 * alpha^2", {.variables = {"m0", "alpha"}});
  const MaterialSplit s = split_per_material(e, kAlpha);
  ASSERT_EQ(s.values.size(), 1u);
  EXPECT_EQ(s.values[0].name, "_m0");
}

}  // namespace
}  // namespace shaderfit
