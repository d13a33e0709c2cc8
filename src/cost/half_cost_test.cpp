// The half lowering (cost/dag.hpp with half = true) and the `sass-half2` target
// (select_sass_half2.cpp). The counts below were checked against nvcc 13.0's SASS of the
// generated __half2 code (--use_fast_math -arch=sm_90; half_compiler_check_test.cpp runs that
// check where nvcc is installed).
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "cost/dag.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/cost/instruction_model.hpp"
#include "shaderfit/cost/per_material.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/expr/precision.hpp"

namespace shaderfit {
namespace {

int half2(const char* formula) {
  return instruction_count(parse_formula(formula), InstructionTarget::SassHalf2);
}

bool has_node(const cost_detail::Dag& dag, Op op) {
  return std::any_of(dag.nodes.begin(), dag.nodes.end(),
                     [&](const cost_detail::DagNode& n) { return n.op == op; });
}

TEST(HalfCost, TargetName) {
  EXPECT_EQ(instruction_target_from_name("sass-half2"), InstructionTarget::SassHalf2);
  EXPECT_EQ(instruction_target_name(InstructionTarget::SassHalf2), "sass-half2");
}

TEST(HalfCost, LoweringKeepsEveryRoundingOfEvaluateHalf) {
  const auto half = [](const char* f) {
    return cost_detail::lower_expression(parse_formula(f), true);
  };
  const auto single = [](const char* f) { return cost_detail::lower_expression(parse_formula(f)); };
  EXPECT_TRUE(has_node(half("fma(a, b, c)"), Op::Fma));
  EXPECT_FALSE(has_node(single("fma(a, b, c)"), Op::Fma));  // float: a * b + c, fused later
  EXPECT_TRUE(has_node(half("a / b"), Op::Div));
  EXPECT_FALSE(has_node(half("a / 4"), Op::Div));  // a * 0.25: the same value, rounded once
  EXPECT_TRUE(has_node(half("a / 3"), Op::Div));
  EXPECT_TRUE(has_node(half("log(a)"), Op::Log));
  EXPECT_FALSE(has_node(half("1 / sqrt(a)"), Op::Rsqrt));  // two roundings, as written
  EXPECT_TRUE(has_node(single("1 / sqrt(a)"), Op::Rsqrt));
  // Literals are binary16 values and fold as evaluate_half computes them.
  const cost_detail::Dag folded = half("a * (0.1 * 3)");
  const double expected = round_to_half(round_to_half(0.1) * round_to_half(3.0));
  EXPECT_TRUE(std::any_of(folded.nodes.begin(), folded.nodes.end(), [&](const auto& n) {
    return n.op == Op::Const && n.value == static_cast<float>(expected);
  }));
  // 2^3 folds along the squaring chain; 1e-8 is zero in half.
  EXPECT_EQ(half2("a * 2^3"), 1);
  EXPECT_EQ(instruction_cost(parse_formula("a + 1e-8"), InstructionTarget::SassHalf2)
                .listing.front()
                .instruction,
            "HADD2 R1, R0, 0, 0");
}

TEST(HalfCost, PackedArithmetic) {
  EXPECT_EQ(half2("r0 + (x - r0) * x^4"), 5);  // float sass 4: one FFMA
  EXPECT_EQ(half2("r0 + (1 - r0) * (1 - x)^5"), 7);
  EXPECT_EQ(half2("a * b + c"), 2);  // no contraction: __hmul2_rn, __hadd2_rn
  EXPECT_EQ(half2("fma(a, b, -c)"), 1);
  EXPECT_EQ(half2("-fma(a, b, c)"), 2);  // a result's negation is an HADD2
  EXPECT_EQ(half2("-(a * b)"), 1);       // ... unless a product takes it
  EXPECT_EQ(half2("-abs(a)"), 1);        // HADD2 d, -|a|, -RZ
  EXPECT_EQ(half2("abs(a - b) * b"), 2);
  EXPECT_EQ(half2("saturate(-a)"), 1);  // HADD2.SAT takes the sign
  EXPECT_EQ(half2("saturate(a * b)"), 2);
  EXPECT_EQ(half2("min(max(a, b), c)"), 2);
  EXPECT_EQ(half2("min(min(a, b), c)"), 1);  // VHMNMX
  EXPECT_EQ(half2("min(min(a, b), min(c, d))"), 2);
  EXPECT_EQ(half2("min(a, min(b, c)) + min(a, b)"), 3);
}

TEST(HalfCost, FunctionsConvertToFloatAndBack) {
  EXPECT_EQ(half2("sqrt(a)"), 5);  // HADD2.F32 x2, MUFU.SQRT x2, F2FP
  EXPECT_EQ(half2("1 / a"), 5);    // h2rcp
  EXPECT_EQ(half2("exp2(a)"), 7);  // + FFMA x2
  EXPECT_EQ(half2("log2(a)"), 9);  // + HSET2, HFMA2 x2
  EXPECT_EQ(half2("exp(a)"), 15);
  EXPECT_EQ(half2("log(a)"), 15);
  EXPECT_EQ(half2("sin(a)"), 7);  // __sinf on each half: + FMUL.RZ x2
  EXPECT_EQ(half2("sin(a) + cos(a)"), 11);
  EXPECT_EQ(half2("exp2(-(a * b))"), 8);      // the sign is free in the conversion
  EXPECT_EQ(half2("sqrt(a) + log2(a)"), 13);  // one conversion of a
  EXPECT_EQ(half2("log2(a) + log(a)"), 21);   // one MUFU.LG2 pair
  EXPECT_EQ(half2("a / b"), 22);              // __h2div: conversions 4, MUFU.RCP 2, 16
  EXPECT_EQ(half2("a / b + c / b"), 41);
  EXPECT_EQ(half2("a / 3"), 18);
  EXPECT_EQ(half2("0.25 / a"), 20);
  EXPECT_EQ(half2("sqrt(a) / a + 1 / a"), 27);
  const InstructionCost c =
      instruction_cost(parse_formula("exp2(a)"), InstructionTarget::SassHalf2);
  EXPECT_EQ(c.mufu, 2);
  EXPECT_EQ(c.fp32, 5);
  EXPECT_EQ(c.weighted, 2 * 8.0 + 5);
  EXPECT_EQ(c.listing.size(), 7u);
  EXPECT_EQ(c.listing.front().instruction, "HADD2.F32 R1, -RZ, R0.H0_H0");
}

TEST(HalfCost, OperatorsWithNoHalfFormThrow) {
  for (const char* f : {"sign(a)", "copysign(a, b)", "select(a >= 0, a, b)", "atan(a)"}) {
    try {
      (void)half2(f);
      ADD_FAILURE() << f;
    } catch (const Error& e) {
      EXPECT_EQ(e.where().source, "formula") << f;
    }
  }
}

TEST(HalfCost, PerMaterialParts) {
  const Expression e = parse_formula("1/(3.14159*alpha^2) * pow(NoH, 2/alpha^2 - 2)");
  const std::vector<std::string> uniform = {"alpha"};
  const SplitCost c = split_instruction_count(e, uniform, InstructionTarget::SassHalf2);
  EXPECT_EQ(c.per_pixel, 18);
  EXPECT_EQ(c.per_material, 37);
}

}  // namespace
}  // namespace shaderfit
