#include "shaderfit/expr/simplify.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "expr/random_expression_test_util.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/expr/print.hpp"

namespace shaderfit {
namespace {

std::string simp(const char* s) {
  ParseOptions o;
  o.variables = {"x", "y"};
  return to_infix(simplify(parse_formula(s, o)));
}

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
  EXPECT_EQ(simp("copysign(3, -0.0) + x"), "-3 + x");
  EXPECT_EQ(simp("select(2 >= 0, x, y)"), "x");
  EXPECT_EQ(simp("select(-1 > 0, x, y)"), "y");
  EXPECT_EQ(simp("select(-0.0 >= 0, x, y)"), "x");
  EXPECT_EQ(simp("select(x - y >= 0, x * 1, x)"), "x");
  EXPECT_EQ(simp("select(x < y, x, y)"), "select(x - y >= 0, y, x)");
  EXPECT_EQ(simp("copysign(x, y) * 1"), "copysign(x, y)");
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
  }
}

}  // namespace
}  // namespace shaderfit
