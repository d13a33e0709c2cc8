#include "shaderfit/eval/evaluate_in.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "shaderfit/core/error.hpp"
#include "shaderfit/expr/parse.hpp"

namespace shaderfit {
namespace {

TEST(EvaluateHalf, RoundsEveryOperation) {
  const Expression e = parse_formula("r0 + (x - r0) * x^4", {.variables = {"r0", "x"}});
  const double r0 = 0.04, x = 0.7;
  // By hand: each value rounded to half.
  const double hr0 = round_to_half(r0), hx = round_to_half(x);
  const double d = round_to_half(hx - hr0);
  const double x2 = round_to_half(hx * hx), x4 = round_to_half(x2 * x2);
  const double want = round_to_half(hr0 + round_to_half(d * x4));
  const double row[] = {r0, x};
  EXPECT_EQ(evaluate_half(e, row), want);
  const double* cols[] = {&row[0], &row[1]};
  std::vector<double> out(1);
  evaluate_in(Precision::Half, e, cols, out);
  EXPECT_EQ(out[0], want);
  evaluate_in(Precision::Float, e, cols, out);
  const float xf = static_cast<float>(x), rf = static_cast<float>(r0);
  const float x2f = xf * xf;
  EXPECT_EQ(out[0], static_cast<double>(rf + (xf - rf) * (x2f * x2f)));
  evaluate_in(Precision::Double, e, cols, out);
  EXPECT_DOUBLE_EQ(out[0], r0 + (x - r0) * std::pow(x, 4));
}

TEST(EvaluateHalf, CancellationAndOverflowShow) {
  // 1 + 1e-4 is 1 in half: (1 + t) - 1 loses t entirely.
  const Expression e = parse_formula("(1 + t) - 1", {.variables = {"t"}});
  const double t[] = {1e-4};
  EXPECT_EQ(evaluate_half(e, t), 0.0);
  const Expression big = parse_formula("x * x", {.variables = {"x"}});
  const double x[] = {300.0};
  EXPECT_TRUE(std::isinf(evaluate_half(big, x)));
  const Expression p = parse_formula("pow(x, 2.2)", {.variables = {"x"}});
  const double v[] = {0.5};
  const double l = round_to_half(std::log2(0.5));
  EXPECT_EQ(evaluate_half(p, v), round_to_half(std::exp2(round_to_half(round_to_half(2.2) * l))));
}

TEST(EvaluateIn, RefusesMissingColumns) {
  const Expression e = parse_formula("x + y", {.variables = {"x", "y"}});
  const double x = 1;
  const double* one[] = {&x};
  std::vector<double> out(1);
  EXPECT_THROW(evaluate_in(Precision::Half, e, one, out), Error);
  const double* missing[] = {&x, nullptr};
  EXPECT_THROW(evaluate_in(Precision::Half, e, missing, out), Error);
}

}  // namespace
}  // namespace shaderfit
