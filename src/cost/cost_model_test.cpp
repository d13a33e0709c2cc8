#include "shaderfit/cost/cost_model.hpp"

#include <gtest/gtest.h>

#include "shaderfit/cost/instruction_model.hpp"
#include "shaderfit/expr/parse.hpp"

namespace shaderfit {
namespace {

double instructions(const char* formula, std::vector<std::string> vars = {"r0", "x"}) {
  ParseOptions opts;
  opts.variables = std::move(vars);
  opts.parameters = {"p", "q"};
  return expression_cost(parse_formula(formula, opts), CostTarget::Instructions);
}

TEST(CostModel, SeedFormulasWithInputX) {
  EXPECT_EQ(instructions("r0 + (x - r0) * x^4"), 4);
  EXPECT_EQ(instructions("r0 + (1 - r0) * x^5"), 5);
  EXPECT_EQ(instructions("(x - r0) * x^4 + r0"), 4);
}

TEST(CostModel, SeedSassCountsWithInputCos) {
  // Seed post 001's listings, with cos_theta as the input: 6, 5 and 6 instructions.
  const std::vector<std::string> v = {"r0", "c", "s"};
  EXPECT_EQ(instructions("r0 + (1 - r0) * (1 - c)^5", v), 6);
  EXPECT_EQ(instructions("r0 + (1 - c - r0) * (1 - c)^4", v), 5);
  EXPECT_EQ(instructions("r0 + (1 - r0 - s * c) * (1 - c)^4", v), 6);
}

// The folds that remove work (a clamp to one value, equal branches, x * 1, x + 0) hold for the
// constants as stated, not for their float32 roundings: a formula scored in float64 with two
// bounds a hair apart, scaled by 4e8, is not a constant, and must not cost as one.
TEST(CostModel, FoldsTakeTheStatedConstants) {
  EXPECT_EQ(instructions("min(max(exp2(x), 1), 1)"), 0);
  EXPECT_GT(instructions("398429440 * min(max(exp2(x), 0.9999999896713022), 1.000000020657396)"
                         " - 398429440"),
            2);
  EXPECT_EQ(instructions("select(x >= 0, 0.5, 0.5)"), 0);
  EXPECT_GT(instructions("3.8477732e15 * select(x >= r0, 0.5, 0.50000000001)"), 0);
  EXPECT_EQ(instructions("x * 1 + r0"), 1);
  EXPECT_EQ(instructions("x * 1.0000000001 + r0"), 1);  // one FFMA either way
  EXPECT_EQ(instructions("x * 1.0000000001"), 1);
  EXPECT_EQ(instructions("x * 1"), 0);
}

TEST(CostModel, IntegerPowersBySquaring) {
  EXPECT_EQ(instructions("x^2"), 1);
  EXPECT_EQ(instructions("x^3"), 2);
  EXPECT_EQ(instructions("x^4"), 2);
  EXPECT_EQ(instructions("x^5"), 3);
  EXPECT_EQ(instructions("x^8"), 3);
  EXPECT_EQ(instructions("x^-2"), 2);
  // Shared intermediates: x^2 and x^4 come from the same chain, and x^2 * x^2 + x^2 is one FMA.
  EXPECT_EQ(instructions("x^2 + x^4"), 2);
  EXPECT_EQ(instructions("x^4 * x^5"), 4);
}

TEST(CostModel, FusionNegationAndSharing) {
  EXPECT_EQ(instructions("r0 * x + 1"), 1);
  EXPECT_EQ(instructions("1 - r0 * x"), 1);
  EXPECT_EQ(instructions("-(r0 * x)"), 1);
  EXPECT_EQ(instructions("1 - r0"), 1);
  EXPECT_EQ(instructions("-r0"), 1);  // a negated input alone still needs an instruction
  EXPECT_EQ(instructions("r0 * x + x * r0"), 2);  // shared product: FMA reusing it, or mul + add
  EXPECT_EQ(instructions("r0 * x + r0 * r0 + x"), 3);  // no reassociation: fma + mul + add
  EXPECT_EQ(instructions("(x + r0) * (x + r0)"), 2);
  EXPECT_EQ(instructions("2 * 3 + x"), 1);  // constants fold
  EXPECT_EQ(instructions("x"), 0);
}

TEST(CostModel, DivisionAndTranscendentals) {
  EXPECT_EQ(instructions("x / r0"), 2);
  EXPECT_EQ(instructions("x / 2"), 1);
  EXPECT_EQ(instructions("rcp(x)"), 1);
  EXPECT_EQ(instructions("1 / x"), 1);
  EXPECT_EQ(instructions("2 / x"), 2);
  EXPECT_EQ(instructions("sqrt(x)"), 1);
  EXPECT_EQ(instructions("exp2(x)"), 1);
  EXPECT_EQ(instructions("exp(x)"), 2);
  EXPECT_EQ(instructions("log(x)"), 2);
  EXPECT_EQ(instructions("pow(x, r0)"), 3);
  EXPECT_EQ(instructions("min(x, r0) + max(x, r0)"), 3);
  EXPECT_EQ(instructions("fma(x, r0, 1)"), 1);
  EXPECT_EQ(instructions("p * x + q"), 1);  // parameters are free operands
  EXPECT_EQ(instructions("sin(x)"), 2);      // range reduction (FMUL) + MUFU.SIN
}

TEST(CostModel, InstructionsIsTheSassCount) {
  ParseOptions opts;
  opts.variables = {"r0", "x"};
  for (const char* f : {"r0 + (x - r0) * x^4", "x / (r0 + 1)", "pow(x, r0) * exp(x) - log2(r0)",
                        "min(x, sqrt(r0)) + cos(x) * x^3"}) {
    const Expression e = parse_formula(f, opts);
    EXPECT_EQ(expression_cost(e, CostTarget::Instructions),
              instruction_count(e, InstructionTarget::Sass))
        << f;
  }
}

TEST(CostModel, NodesIsTheSizeOfThePostfixArray) {
  ParseOptions opts;
  opts.variables = {"r0", "x"};
  EXPECT_EQ(expression_cost(parse_formula("r0 + (x - r0) * x^4", opts), CostTarget::Nodes), 8);
  EXPECT_EQ(expression_cost(parse_formula("x", opts), CostTarget::Nodes), 1);
}

TEST(CostModel, TargetNames) {
  EXPECT_EQ(cost_target_from_name("nodes"), CostTarget::Nodes);
  EXPECT_EQ(cost_target_from_name("instructions"), CostTarget::Instructions);
  EXPECT_FALSE(cost_target_from_name("sass").has_value());
  EXPECT_EQ(cost_target_name(CostTarget::Nodes), "nodes");
}

}  // namespace
}  // namespace shaderfit
