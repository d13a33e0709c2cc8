#include "shaderfit/cost/instruction_model.hpp"

#include <gtest/gtest.h>

#include "shaderfit/core/error.hpp"
#include "shaderfit/expr/parse.hpp"

namespace shaderfit {
namespace {

Expression parse(const std::string& f, std::vector<std::string> params = {}) {
  ParseOptions o;
  o.parameters = std::move(params);
  return parse_formula(f, o);
}
int sass(const std::string& f) { return instruction_count(parse(f), InstructionTarget::Sass); }
int ptx(const std::string& f) { return instruction_count(parse(f), InstructionTarget::Ptx); }
int generic(const std::string& f) {
  return instruction_count(parse(f), InstructionTarget::Generic);
}

TEST(InstructionModel, SeedListingsCountSixFiveSix) {
  // Seed 001's SASS listings, with cos_theta and r0 (and the shape parameter s) as inputs.
  EXPECT_EQ(sass("r0 + (1 - r0) * (1 - cos_theta)^5"), 6);
  EXPECT_EQ(sass("r0 + (1 - cos_theta - r0) * (1 - cos_theta)^4"), 5);
  EXPECT_EQ(sass("r0 + (1 - r0 - s * cos_theta) * (1 - cos_theta)^4"), 6);
  EXPECT_EQ(instruction_count(parse("r0 + (1 - r0 - s * cos_theta) * (1 - cos_theta)^4", {"s"}),
                              InstructionTarget::Sass),
            6);
}

TEST(InstructionModel, SchlickListingMatchesTheSeed) {
  const InstructionCost c =
      instruction_cost(parse("r0 + (1 - r0) * (1 - cos_theta)^5"), InstructionTarget::Sass);
  ASSERT_EQ(c.listing.size(), 6u);
  EXPECT_EQ(c.listing[0].instruction, "FADD.FTZ R2, -R0, 1");
  EXPECT_EQ(c.listing[0].comment, "1 - r0");
  EXPECT_EQ(c.listing[1].comment, "1 - cos_theta");
  EXPECT_EQ(c.listing[2].comment, "(1 - cos_theta)^2");
  EXPECT_EQ(c.listing[3].comment, "(1 - cos_theta)^4");
  EXPECT_EQ(c.listing[4].comment, "(1 - cos_theta)^5");
  EXPECT_EQ(c.listing[5].instruction.rfind("FFMA.FTZ", 0), 0u);
  EXPECT_EQ(c.fp32, 6);
  EXPECT_DOUBLE_EQ(c.weighted, 6.0);
  const std::string text = format_listing(c);
  EXPECT_NE(text.find("FADD.FTZ R2, -R0, 1"), std::string::npos);
  EXPECT_NE(text.find(" ; 1 - r0\n"), std::string::npos);
}

TEST(InstructionModel, FusionNegationAndImmediates) {
  EXPECT_EQ(sass("a * b + c"), 1);
  EXPECT_EQ(sass("a * b - c"), 1);
  EXPECT_EQ(sass("c - a * b"), 1);
  EXPECT_EQ(sass("1 - a"), 1);
  EXPECT_EQ(sass("-a"), 1);        // the result must be positive: FADD -a, -RZ
  EXPECT_EQ(sass("-(a * b)"), 1);  // folds into the product
  EXPECT_EQ(sass("a * 2.5 + 0.5"), 1);
  EXPECT_EQ(ptx("a * b - c"), 2);  // neg.f32 + fma
  EXPECT_EQ(generic("a * b - c"), 2);
  EXPECT_EQ(generic("-a"), 1);
  EXPECT_EQ(generic("a - b"), 1);
}

TEST(InstructionModel, SharedSubexpressionsAndPowers) {
  EXPECT_EQ(sass("x^2"), 1);
  EXPECT_EQ(sass("x^3"), 2);
  EXPECT_EQ(sass("x^4"), 2);
  EXPECT_EQ(sass("x^5"), 3);
  EXPECT_EQ(sass("x^8"), 3);
  EXPECT_EQ(sass("x^-2"), 2);
  EXPECT_EQ(sass("x^2 + x^4"), 2);          // x^4 = x^2 * x^2 + x^2 as one FFMA
  EXPECT_EQ(sass("(a + b) * (b + a)"), 2);  // commutative operands are one value
  EXPECT_EQ(sass("sqrt(a) + sqrt(a)"), 2);
}

// Powers of powers multiply their exponents; the listing's comments name x^k while k fits, and
// beyond 2^30 print the product (fuzz/regressions/formula/integer_powers_nested_beyond_int).
TEST(InstructionModel, NestedPowersBeyondIntPrintAsProducts) {
  EXPECT_EQ(sass("(x^16)^16"), 8);
  const InstructionCost c = instruction_cost(parse("((x^16)^16)^16"), InstructionTarget::Sass);
  EXPECT_EQ(c.listing.back().comment, "x^4096");
  const InstructionCost deep = instruction_cost(
      parse("((((((((x^16)^16)^16)^16)^16)^16)^16)^16)^16"), InstructionTarget::Sass);
  EXPECT_EQ(deep.instructions, 36);
  for (const ListingLine& line : deep.listing)
    EXPECT_EQ(line.comment.find("^-"), std::string::npos) << line.comment;
  EXPECT_EQ(deep.listing[29].comment, "x^1073741824");  // 2^30
  EXPECT_EQ(deep.listing.back().comment, "(x^1073741824 * x^1073741824)^32");
}

TEST(InstructionModel, MufuOperations) {
  EXPECT_EQ(sass("sqrt(a)"), 1);
  EXPECT_EQ(sass("rsqrt(a)"), 1);
  EXPECT_EQ(sass("1 / sqrt(a)"), 1);  // nvcc makes it rsqrt
  EXPECT_EQ(sass("a / b"), 2);        // MUFU.RCP + FMUL
  EXPECT_EQ(sass("a / 4"), 1);        // a * 0.25
  EXPECT_EQ(sass("exp(a)"), 2);
  EXPECT_EQ(sass("log(a)"), 2);
  EXPECT_EQ(sass("log(a) + b"), 2);       // ln 2 scale fused into an FFMA
  EXPECT_EQ(sass("sin(a)"), 2);           // FMUL.RZ + MUFU.SIN
  EXPECT_EQ(sass("sin(a) + cos(a)"), 4);  // the FMUL.RZ is shared
  EXPECT_EQ(sass("pow(a, b)"), 3);
  EXPECT_EQ(sass("exp2(-a)"), 2);    // MUFU takes no negated operand
  EXPECT_EQ(sass("abs(a) * b"), 1);  // |a| is an operand modifier
  EXPECT_EQ(sass("sqrt(abs(a))"), 2);
  EXPECT_EQ(sass("saturate(a * b)"), 1);  // FMUL.SAT
  EXPECT_EQ(sass("saturate(a + b)"), 2);
  EXPECT_EQ(sass("min(a, b)"), 1);
  EXPECT_EQ(ptx("sin(a)"), 1);
  EXPECT_EQ(ptx("a / b"), 2);
  EXPECT_EQ(generic("a / b"), 1);
  EXPECT_EQ(generic("exp(a)"), 1);
}

// sign, copysign and select: the counts nvcc and glslang gave (docs/cost-model.md; checked
// against the compilers in src/codegen/compiler_check_test.cpp where they are installed).
TEST(InstructionModel, SignCopysignSelect) {
  struct Row {
    const char* formula;
    int sass, ptx, generic;
  };
  const Row rows[] = {
      {"select(x - y >= 0, x * y, x + 1)", 3, 4, 4},  // x >= y ? ...: no subtraction
      {"select(x >= 0, 2, 0.5) * y", 3, 3, 3},
      {"sign(x) * y + sign(y)", 7, 9, 10},
      {"copysign(x, y) * copysign(1, y) + copysign(x * x, -y)", 6, 6, 11},
      {"select(-x >= 0, y, x * x) + select(-x >= 0, x * x, y) * y", 5, 5, 7},
      {"select(x * y >= 0, sqrt(x), rcp(y))", 4, 5, 5},
      {"sign(x - y) * copysign(y, x - y)", 6, 7, 9},
      {"copysign(x + y, x - y) * 0.5", 4, 4, 6},
      // Folds: a literal condition, equal branches, a literal sign.
      {"select(2 >= 0, x, y) + select(x >= 0, y, y)", 1, 1, 1},
      {"copysign(x, -2) * y", 1, 3, 3},
  };
  for (const Row& r : rows) {
    const Expression e = parse_formula(r.formula);
    EXPECT_EQ(instruction_count(e, InstructionTarget::Sass), r.sass) << r.formula;
    EXPECT_EQ(instruction_count(e, InstructionTarget::Ptx), r.ptx) << r.formula;
    EXPECT_EQ(instruction_count(e, InstructionTarget::Generic), r.generic) << r.formula;
  }
  const InstructionCost c =
      instruction_cost(parse_formula("select(x >= 0, 2, y * y)"), InstructionTarget::Sass);
  EXPECT_EQ(c.instructions, 2);  // FSETP, FMUL under the predicate
  EXPECT_EQ(c.minmax, 1);
  EXPECT_EQ(c.listing[1].instruction.rfind("FSETP.GE", 0), 0u) << format_listing(c);
}

// asin ... erf: the instructions nvcc emits for CUDA's asinf ... erff (sm_90, --use_fast_math;
// docs/cost-model.md, "Library functions"), one OpExtInst in SPIR-V but erf, whose helper
// function counts; checked against the compilers in
// CompilerCheck.LibraryFunctionsAgainstNvccAndGlslang where they are installed.
TEST(InstructionModel, LibraryFunctions) {
  struct Row {
    const char* formula;
    int sass, ptx, generic;
    int fp32, minmax, mufu;  // of the SASS
  };
  const Row alone[] = {
      {"asin(x)", 22, 26, 1, 15, 6, 1}, {"acos(x)", 24, 29, 1, 17, 6, 1},
      {"atan(x)", 17, 20, 1, 12, 4, 1}, {"atan2(x, y)", 33, 32, 1, 21, 11, 1},
      {"tanh(x)", 1, 1, 1, 0, 0, 1},    {"erf(x)", 23, 24, 36, 11, 11, 1},
  };
  for (const Row& r : alone) {
    const Expression e = parse_formula(r.formula);
    const InstructionCost c = instruction_cost(e, InstructionTarget::Sass);
    EXPECT_EQ(c.instructions, r.sass) << r.formula;
    EXPECT_EQ(c.fp32, r.fp32) << r.formula;
    EXPECT_EQ(c.minmax, r.minmax) << r.formula;
    EXPECT_EQ(c.mufu, r.mufu) << r.formula;
    EXPECT_DOUBLE_EQ(c.weighted, r.fp32 + 2.0 * r.minmax + 8.0 * r.mufu) << r.formula;
    EXPECT_EQ(instruction_count(e, InstructionTarget::Ptx), r.ptx) << r.formula;
    EXPECT_EQ(instruction_count(e, InstructionTarget::Generic), r.generic) << r.formula;
  }
  // In formulas (the counts nvcc and glslang gave): odd functions move an operand's sign to
  // their result; acos reads it, and of a negated product costs the product's negation.
  const Row in_formulas[] = {
      {"asin(x) * y", 23, 27, 2},        {"acos(x * y)", 25, 30, 2},
      {"atan2(x, y) * 2", 34, 33, 2},    {"tanh(x * y + 1)", 2, 2, 3},
      {"erf(x) * y", 24, 25, 37},        {"atan(-x * y) * y", 19, 23, 4},
      {"asin(-x * y)", 24, 28, 3},       {"acos(1 - x)", 25, 30, 2},
      {"atan2(x, -(x * y))", 34, 34, 3}, {"-atan(x)", 18, 21, 2},
      {"acos(-x * y)", 26, 31, 3},       {"atan2(-x, y + 1)", 35, 34, 3},
      {"erf(x) + erf(y)", 47, 49, 73},   {"atan(x, y)", 33, 32, 1},
  };
  for (const Row& r : in_formulas) {
    const Expression e = parse_formula(r.formula);
    EXPECT_EQ(instruction_count(e, InstructionTarget::Sass), r.sass) << r.formula;
    EXPECT_EQ(instruction_count(e, InstructionTarget::Ptx), r.ptx) << r.formula;
    EXPECT_EQ(instruction_count(e, InstructionTarget::Generic), r.generic) << r.formula;
  }
  // The listing names the function; its last line is the value.
  const InstructionCost c = instruction_cost(parse_formula("atan(x)"), InstructionTarget::Sass);
  EXPECT_EQ(c.listing.front().comment, "atanf 1/17");
  EXPECT_EQ(c.listing.back().comment, "atan(x)");
  EXPECT_EQ(c.listing.back().instruction.rfind("FSEL", 0), 0u) << format_listing(c);
  const InstructionCost g = instruction_cost(parse_formula("erf(x)"), InstructionTarget::Generic);
  EXPECT_EQ(g.listing.front().comment, "sf_erf 1/36");
  EXPECT_NE(g.listing.back().instruction.find("OpSelect"), std::string::npos) << format_listing(g);
  // Constant arguments fold.
  EXPECT_EQ(sass("atan2(1, 2) * x + erf(0.5)"), 1);
}

TEST(InstructionModel, WeightsFollowTheThroughputTable) {
  EXPECT_DOUBLE_EQ(throughput_weight(InstructionTarget::Sass, InstructionUnit::Fp32), 1.0);
  EXPECT_DOUBLE_EQ(throughput_weight(InstructionTarget::Sass, InstructionUnit::Mufu), 8.0);
  EXPECT_DOUBLE_EQ(throughput_weight(InstructionTarget::Sass, InstructionUnit::MinMax), 2.0);
  const InstructionCost c = instruction_cost(parse("a / b"), InstructionTarget::Sass);
  EXPECT_EQ(c.mufu, 1);
  EXPECT_EQ(c.fp32, 1);
  EXPECT_DOUBLE_EQ(c.weighted, 9.0);
}

TEST(InstructionModel, LeavesAndConstantsAreFree) {
  EXPECT_EQ(sass("a"), 0);
  EXPECT_EQ(sass("1 + 2 * 3"), 0);
  EXPECT_EQ(sass("a * 1"), 0);
}

TEST(InstructionModel, TargetNames) {
  EXPECT_EQ(instruction_target_from_name("sass"), InstructionTarget::Sass);
  EXPECT_EQ(instruction_target_from_name("ptx"), InstructionTarget::Ptx);
  EXPECT_EQ(instruction_target_from_name("generic"), InstructionTarget::Generic);
  EXPECT_FALSE(instruction_target_from_name("x86").has_value());
  EXPECT_EQ(instruction_target_name(InstructionTarget::Generic), "generic");
}

TEST(InstructionModel, EmptyExpressionIsAnError) {
  EXPECT_THROW(instruction_count(Expression{}, InstructionTarget::Sass), Error);
}

}  // namespace
}  // namespace shaderfit
