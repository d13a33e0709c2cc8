#include "shaderfit/expr/simplify.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "expr/random_expression_test_util.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/expr/print.hpp"

namespace shaderfit {
namespace {

std::string simp(const char* s, const SimplifyOptions& options = {}) {
  ParseOptions o;
  o.variables = {"x", "y"};
  return to_infix(simplify(parse_formula(s, o), options));
}

std::string regroup(const char* s) { return simp(s, {.regroup_constants = true}); }

TEST(Simplify, Rules) {
  EXPECT_EQ(simp("(x * x) * 1 + 0"), "x^2");
  EXPECT_EQ(simp("x - x"), "0");
  EXPECT_EQ(simp("x * x^3"), "x^4");
  EXPECT_EQ(simp("x^2 * x^2"), "x^4");
  EXPECT_EQ(simp("(x^2)^3"), "x^6");
  EXPECT_EQ(simp("x^3 / x"), "x^2");
  EXPECT_EQ(simp("x^2 / x^2"), "1");
  EXPECT_EQ(simp("2 * 3 + x"), "6 + x");
  EXPECT_EQ(simp("-(-x)"), "x");
  EXPECT_EQ(simp("x + -y"), "x - y");
  EXPECT_EQ(simp("x - -y"), "x + y");
  EXPECT_EQ(simp("0 - x"), "-x");
  EXPECT_EQ(simp("1 / x"), "rcp(x)");
  EXPECT_EQ(simp("(-x)^2"), "x^2");
  EXPECT_EQ(simp("fma(x, y, 0)"), "x * y");
  EXPECT_EQ(simp("x * 0 + y"), "y");
  EXPECT_EQ(simp("1 / 0 + x"), "rcp(0) + x");  // folding to inf is not done
  EXPECT_EQ(simp("x^8 * x^9"), "x^8 * x^9");   // would leave the exponent range
  EXPECT_EQ(simp("sign(-2) * x"), "-x");
  EXPECT_EQ(simp("sign(sign(x))"), "sign(x)");
  EXPECT_EQ(simp("copysign(3, -0.0) + x"), "x - 3");
  EXPECT_EQ(simp("select(2 >= 0, x, y)"), "x");
  EXPECT_EQ(simp("select(-1 > 0, x, y)"), "y");
  EXPECT_EQ(simp("select(-0.0 >= 0, x, y)"), "x");
  EXPECT_EQ(simp("select(x - y >= 0, x * 1, x)"), "x");
  EXPECT_EQ(simp("select(x < y, x, y)"), "select(x - y >= 0, y, x)");
  EXPECT_EQ(simp("copysign(x, y) * 1"), "copysign(x, y)");
  // Constants fold; atan2 reads the signs of zeros (atan2(-0, -1) = -pi), so a zero that may be
  // -0 stays as it is below it.
  EXPECT_EQ(simp("atan2(0, -1) + erf(0) + x"), "3.141592653589793 + x");
  EXPECT_EQ(simp("atan2(x * 0, -1)"), "atan2(0 * x, -1)");
  EXPECT_EQ(simp("atan2(y, x * 0)"), "atan2(y, 0 * x)");
  EXPECT_EQ(simp("asin(x * 1) + tanh(x + 0)"), "asin(x) + tanh(x)");
}

TEST(Simplify, RegroupsConstantsOnlyWhenAsked) {
  EXPECT_EQ(simp("2 * (3 * x)"), "2 * (3 * x)");
  EXPECT_EQ(simp("pow(pow(3, x), x)"), "pow(pow(3, x), x)");
  EXPECT_EQ(simp("0.5 * (x - 3) + 1"), "0.5 * (x - 3) + 1");
}

TEST(Simplify, ATermAddedAndTakenAwayCancels) {
  EXPECT_EQ(regroup("x^2 + 0.5 - y + x - x"), "x^2 + 0.5 - y");
  EXPECT_EQ(regroup("(x + y) - x"), "y");
  EXPECT_EQ(regroup("y + (x - y)"), "x");
  EXPECT_EQ(regroup("(x - y) + y"), "x");
  EXPECT_EQ(simp("x^2 + y - y"), "x^2 + y - y");  // rounds differently: only when regrouping
}

TEST(Simplify, MergesConstantProducts) {
  EXPECT_EQ(regroup("2 * (3 * x)"), "6 * x");
  EXPECT_EQ(regroup("(x * 3) * 2"), "6 * x");
  EXPECT_EQ(regroup("2 * (x * y * 3)"), "x * y * 6");
  EXPECT_EQ(regroup("2 * (x / 8)"), "x / 4");
  EXPECT_EQ(regroup("(6 * x) / 4"), "1.5 * x");
  EXPECT_EQ(regroup("(x / 2) / 4"), "x / 8");
  EXPECT_EQ(regroup("3 * -x"), "-3 * x");
  EXPECT_EQ(regroup("2 * -(3 * x)"), "-6 * x");
  EXPECT_EQ(regroup("x / 3"), "x / 3");  // nothing to merge into: stays as written
  EXPECT_EQ(regroup("2 * (x + y)"), "2 * (x + y)");
}

TEST(Simplify, CollectsLikeTerms) {
  EXPECT_EQ(regroup("0.25 * x + 0.5 * x"), "0.75 * x");
  EXPECT_EQ(regroup("x * 3 - x"), "2 * x");
  EXPECT_EQ(regroup("0.5 * x^2 - -x^2"), "1.5 * x^2");
  // A luminance of a gray color: dot(vec3(y), vec3(0.25, 0.5, 0.25)) written out.
  EXPECT_EQ(regroup("0.25 * y + 0.5 * y + 0.25 * (y * 1)"), "y");
  EXPECT_EQ(regroup("(x + 0.5 * y) + 0.25 * y"), "x + 0.75 * y");
  EXPECT_EQ(regroup("(0.5 * y - x) + 0.25 * y"), "0.75 * y - x");
  EXPECT_EQ(regroup("(x - 0.5 * y) + 0.25 * y"), "x - 0.25 * y");
  EXPECT_EQ(regroup("x + x"), "x + x");  // no constant: stays as written
  EXPECT_EQ(simp("0.25 * x + 0.5 * x"), "0.25 * x + 0.5 * x");  // rounds differently
}

TEST(Simplify, AbsorbsScaleAndOffsetWrappers) {
  EXPECT_EQ(regroup("2 * (3 * x + 1) + 5"), "6 * x + 7");
  EXPECT_EQ(regroup("0.5 * (x * 4 - y * 2) - 1"), "2 * x - y - 1");
  EXPECT_EQ(regroup("0.5 * (x - 3) + 1"), "0.5 * (x - 1)");
  EXPECT_EQ(regroup("(x + 1) + 2"), "x + 3");
  EXPECT_EQ(regroup("2 + (x - 5)"), "x - 3");
  EXPECT_EQ(regroup("4 - (x - 1)"), "5 - x");
  EXPECT_EQ(regroup("1 - (3 - x)"), "x - 2");
  EXPECT_EQ(regroup("(x * y - 4) / 2 + 2"), "x * y / 2");
  EXPECT_EQ(regroup("fma(x, y, 1) + 2"), "fma(x, y, 3)");
  EXPECT_EQ(regroup("3 * fma(2, x, 1)"), "fma(6, x, 3)");
  // A large constant added and subtracted cancels into the small one left.
  EXPECT_EQ(regroup("0.25 * (x * y - 65536) + 16384"), "0.25 * (x * y)");
  // Not where a zero's sign reaches the result through copysign.
  EXPECT_EQ(regroup("copysign(1, 2 * (3 * x))"), "copysign(1, 2 * (3 * x))");
}

TEST(Simplify, FoldsPowersOfPowers) {
  EXPECT_EQ(regroup("pow(pow(3, x), x)"), "pow(3, x^2)");
  EXPECT_EQ(regroup("pow(pow(x, y), 2 * x)"), "pow(x, y * (2 * x))");
  // With a cost that counts pow dearer than exp2, the exp2 form with c = log2(3).
  SimplifyOptions dear_pow{.regroup_constants = true, .cost = [](const Expression& e) {
                             double c = 0;
                             for (const Node& n : e.nodes) c += n.op == Op::Pow ? 10 : 1;
                             return c;
                           }};
  EXPECT_EQ(simp("pow(pow(4, x), x)", dear_pow), "exp2(2 * x^2)");
  // A tie keeps pow.
  SimplifyOptions flat{.regroup_constants = true, .cost = [](const Expression&) { return 1.0; }};
  EXPECT_EQ(simp("pow(pow(4, x), x)", flat), "pow(4, x^2)");
}

// Simplifies 10,000 random formulas with `options` and compares them with the originals at 8
// random points each where every intermediate is finite and the original well conditioned.
// Returns the points compared and the formulas the options made smaller than plain simplify.
std::pair<int, int> expect_values_kept(const SimplifyOptions& options, std::uint64_t seed) {
  Rng rng(seed);
  const std::vector<std::string> names = {"x", "y"};
  int compared = 0, changed = 0;
  for (int i = 0; i < 10000; ++i) {
    Expression e = testing::random_expression(rng, names, 1 + static_cast<int>(i % 6), i % 4 == 0);
    Expression s = simplify(e, options);
    EXPECT_LE(s.size(), e.size()) << to_infix(e);
    if (s.size() < simplify(e).size()) ++changed;
    for (int r = 0; r < 8; ++r) {
      const double x = uniform(rng, -3.0, 3.0), y = uniform(rng, -3.0, 3.0);
      bool finite = true;
      const double orig = testing::eval_reference<double>(e, {x, y}, &finite);
      if (!finite) continue;
      const long double orig_ld = testing::eval_reference<long double>(e, {x, y});
      if (!(std::fabs(static_cast<double>(orig_ld) - orig) <= 1e-7 * (1.0 + std::fabs(orig))))
        continue;
      const long double simp_ld = testing::eval_reference<long double>(s, {x, y});
      EXPECT_NEAR(static_cast<double>(simp_ld), static_cast<double>(orig_ld),
                  1e-6 * (1.0 + std::fabs(orig)))
          << to_infix(e) << "  =>  " << to_infix(s) << "  at x=" << x << " y=" << y;
      ++compared;
    }
  }
  return {compared, changed};
}

TEST(Simplify, RegroupingKeepsValuesOnRandomExpressions) {
  const auto [compared, changed] = expect_values_kept({.regroup_constants = true}, 4242);
  EXPECT_GT(compared, 20000);
  EXPECT_GT(changed, 40);  // the rules do fire on random formulas (50 of these 10,000)
}

TEST(Simplify, MergesCalls) {
  const SimplifyOptions m{.merge_calls = true};
  EXPECT_EQ(simp("rcp(x) * rcp(y + 1)", m), "rcp(x * (y + 1))");
  EXPECT_EQ(simp("sqrt(x) * sqrt(y)", m), "sqrt(x * y)");
  EXPECT_EQ(simp("rsqrt(x) * rsqrt(y)", m), "rsqrt(x * y)");
  EXPECT_EQ(simp("exp2(x) * exp2(y)", m), "exp2(x + y)");
  EXPECT_EQ(simp("exp2(x) / exp2(y)", m), "exp2(x - y)");
  EXPECT_EQ(simp("exp(x) * exp(2 * y)", m), "exp(x + 2 * y)");
  EXPECT_EQ(simp("log2(x) + log2(y)", m), "log2(x * y)");
  EXPECT_EQ(simp("pow(x, 1.5) * pow(y, 1.5)", m), "pow(x * y, 1.5)");
  EXPECT_EQ(simp("pow(x, 1.5) * pow(y, 2.5)", m), "pow(x, 1.5) * pow(y, 2.5)");
  EXPECT_EQ(simp("x / y / (x + 1)", m), "x / (y * (x + 1))");
  EXPECT_EQ(simp("rcp(x) / y", m), "rcp(x * y)");
  EXPECT_EQ(simp("x / rcp(y)", m), "x * y");
  EXPECT_EQ(simp("x / y * rcp(x + 2)", m), "x / (y * (x + 2))");
  // One level into a product or a sum.
  EXPECT_EQ(simp("0.5 * rcp(x) * rcp(y)", m), "0.5 * rcp(x * y)");
  EXPECT_EQ(simp("rcp(x) * 0.5 * rcp(y)", m), "0.5 * rcp(x * y)");
  EXPECT_EQ(simp("x + log2(x) + log2(y)", m), "x + log2(x * y)");
  // Only when asked, and not where a zero's sign reaches the result.
  EXPECT_EQ(simp("rcp(x) * rcp(y)"), "rcp(x) * rcp(y)");
  EXPECT_EQ(simp("copysign(1, rcp(x) * rcp(y))", m), "copysign(1, rcp(x) * rcp(y))");
}

TEST(Simplify, MergingCallsKeepsValuesOnRandomExpressions) {
  const auto [compared, changed] =
      expect_values_kept({.regroup_constants = true, .merge_calls = true}, 5151);
  EXPECT_GT(compared, 20000);
  EXPECT_GT(changed, 60);
}

TEST(Simplify, KeepsValuesOnRandomExpressions) {
  Rng rng(777);
  const std::vector<std::string> names = {"x", "y"};
  int compared = 0;
  for (int i = 0; i < 10000; ++i) {
    Expression e = testing::random_expression(rng, names, 1 + static_cast<int>(i % 6), i % 4 == 0);
    Expression s = simplify(e);
    EXPECT_LE(s.size(), e.size()) << to_infix(e);
    for (int r = 0; r < 8; ++r) {
      const double x = uniform(rng, -3.0, 3.0), y = uniform(rng, -3.0, 3.0);
      // Only points where every intermediate is finite: there the rules are exact up to rounding
      // (signed zeros count as equal, as under shader compilers' fast math; they can only show
      // through an infinite intermediate such as 1 / -0).
      bool finite = true;
      const double orig = testing::eval_reference<double>(e, {x, y}, &finite);
      if (!finite) continue;
      const long double orig_ld = testing::eval_reference<long double>(e, {x, y});
      // Skip ill-conditioned points: where double and long double disagree the expression
      // amplifies rounding, and reordering by the simplifier is indistinguishable from it.
      if (!(std::fabs(static_cast<double>(orig_ld) - orig) <= 1e-7 * (1.0 + std::fabs(orig))))
        continue;
      const long double simp_ld = testing::eval_reference<long double>(s, {x, y});
      ASSERT_NEAR(static_cast<double>(simp_ld), static_cast<double>(orig_ld),
                  1e-6 * (1.0 + std::fabs(orig)))
          << to_infix(e) << "  =>  " << to_infix(s) << "  at x=" << x << " y=" << y;
      ++compared;
    }
  }
  EXPECT_GT(compared, 20000);
}

TEST(Simplify, IsIdempotent) {
  Rng rng(99);
  for (int i = 0; i < 2000; ++i) {
    Expression e = testing::random_expression(rng, {"x", "y"}, 5);
    Expression s = simplify(e);
    Expression t = simplify(s);
    EXPECT_LE(t.size(), s.size()) << to_infix(e);
    for (const SimplifyOptions& o : {SimplifyOptions{.regroup_constants = true},
                                     SimplifyOptions{.regroup_constants = true, .merge_calls = true}}) {
      Expression u = simplify(e, o);
      EXPECT_LE(simplify(u, o).size(), u.size()) << to_infix(e);
    }
  }
}

}  // namespace
}  // namespace shaderfit
