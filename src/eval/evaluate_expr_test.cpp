#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "eval/eval_test_support.hpp"
#include "eval/interpreter.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/core/random.hpp"
#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/expr/expression.hpp"

namespace shaderfit {
namespace {

using eval_detail::Backend;
using eval_detail::kBatchRows;
using namespace eval_test;

// Same bits, except that NaNs match NaNs and zeros match zeros: the sign of min(+0, -0) is
// left open by C, and compilers inline fmin with either operand order.
template <typename T>
bool same_value(T a, T b) {
  return same_bits(a, b) || (std::isnan(a) && std::isnan(b)) || (a == 0 && b == 0);
}

// ---------------------------------------------------------------------------------------------
// Whole expressions.

TEST(EvalExpr, ArithmeticExpressionsAreBitExact) {
  Rng rng(11);
  for (int trial = 0; trial < 200; ++trial) {
    const Expression e = random_expression(rng, 3, /*arithmetic_only=*/true);
    Inputs<double> in(rng, 3, 1000, -3.0, 3.0);
    const std::vector<double> got = run<double>(e, in);
    for (std::size_t i = 0; i < got.size(); ++i) {
      const double want = evaluate_scalar(e, in.row(i));
      ASSERT_TRUE(same_value(got[i], want))
          << "trial " << trial << " row " << i << ": " << got[i] << " vs " << want;
    }
    Inputs<float> inf(in);
    const std::vector<float> simd = run<float>(e, inf);
    const std::vector<float> scalar = run<float>(e, inf, {}, Backend::Scalar);
    for (std::size_t i = 0; i < simd.size(); ++i)
      ASSERT_TRUE(same_value(simd[i], scalar[i]))
          << "trial " << trial << " row " << i << ": " << simd[i] << " vs " << scalar[i];
  }
}

TEST(EvalExpr, RandomExpressionsAgreeWithScalar) {
  // All ops. Transcendental ops differ from libm by a few ulp, and an expression can magnify
  // that without bound (a difference that crosses zero before a log), so a row may disagree;
  // nearly all must agree to 1e-9 relative (none disagreed when this was written).
  Rng rng(12);
  std::size_t rows_total = 0, disagree = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const Expression e = random_expression(rng, 3, /*arithmetic_only=*/false);
    Inputs<double> in(rng, 3, 500, -3.0, 3.0);
    const std::vector<double> got = run<double>(e, in);
    for (std::size_t i = 0; i < got.size(); ++i) {
      const double want = evaluate_scalar(e, in.row(i));
      ++rows_total;
      if (!close(got[i], want, 1e-9)) ++disagree;
    }
  }
  EXPECT_LE(disagree, rows_total / 10000) << disagree << " of " << rows_total << " rows";
}

TEST(EvalExpr, FloatCloseToDouble) {
  Rng rng(13);
  for (const Expression& e : formulas()) {
    Inputs<double> in(rng, e.variables.size(), 5000, 0.05, 1.0);
    Inputs<float> inf(in);
    const std::vector<double> d = run<double>(e, in);
    const std::vector<float> f = run<float>(e, inf);
    for (std::size_t i = 0; i < d.size(); ++i)
      ASSERT_NEAR(f[i], d[i], 2e-5 * std::max(1.0, std::abs(d[i]))) << "row " << i;
  }
}

TEST(EvalExpr, ThreadCountsGiveIdenticalResults) {
  Rng rng(14);
  for (const Expression& e : formulas()) {
    Inputs<float> in(rng, e.variables.size(), 300001, -2.0, 2.0);
    const std::vector<float> one = run<float>(e, in, {.threads = 1});
    for (int threads : {2, 4, 0}) {
      const std::vector<float> many =
          run<float>(e, in, {.threads = threads, .min_rows_per_task = 1000});
      ASSERT_EQ(0, std::memcmp(one.data(), many.data(), one.size() * sizeof(float)))
          << threads << " threads";
    }
  }
}

template <typename T>
void check_row_counts() {
  Rng rng(15);
  constexpr std::size_t B = kBatchRows<T>;
  for (std::size_t rows : {std::size_t{0}, std::size_t{1}, std::size_t{7}, B - 1, B, B + 1,
                           2 * B + 3, std::size_t{100003}}) {
    for (const Expression& e : formulas()) {
      Inputs<T> in(rng, e.variables.size(), rows, 0.05, 1.0);
      const std::vector<T> simd = run<T>(e, in, {.min_rows_per_task = 4096});
      const std::vector<T> scalar = run<T>(e, in, {.threads = 1}, Backend::Scalar);
      ASSERT_EQ(simd.size(), rows);
      for (std::size_t i = 0; i < rows; ++i)
        ASSERT_TRUE(close(static_cast<double>(simd[i]), static_cast<double>(scalar[i]),
                          sizeof(T) == 4 ? 1e-5 : 1e-12, 1.0))
            << rows << " rows, row " << i << ": " << simd[i] << " vs " << scalar[i];
    }
  }
}

TEST(EvalExpr, RowCountsFloat) { check_row_counts<float>(); }
TEST(EvalExpr, RowCountsDouble) { check_row_counts<double>(); }

TEST(EvalExpr, LeafRoots) {
  Expression e;
  e.variables = {"x"};
  e.parameters = {"p"};
  e.parameter_values = {2.5};
  const std::vector<double> x = {1.0, -2.0, 3.0};
  const double* columns[] = {x.data()};
  std::vector<double> out(3);
  e.nodes = {Node::variable(0)};
  evaluate(e, columns, out);
  EXPECT_EQ(out, x);
  e.nodes = {Node::constant(-4.0)};
  evaluate(e, columns, out);
  EXPECT_EQ(out, std::vector<double>(3, -4.0));
  e.nodes = {Node::parameter(0)};
  evaluate(e, columns, out);
  EXPECT_EQ(out, std::vector<double>(3, 2.5));
  EXPECT_EQ(evaluate_scalar(e, std::vector<double>{7.0}), 2.5);
}

TEST(EvalExpr, ParametersAndConstants) {
  // r0 + (x - r0) * x^4 with r0 a parameter, and a constant offset.
  Expression e;
  e.variables = {"x"};
  e.parameters = {"r0"};
  e.parameter_values = {0.04};
  e.nodes = {Node::parameter(0),     Node::variable(0),      Node::parameter(0),
             Node::op_node(Op::Sub), Node::variable(0),      Node::ipow(4),
             Node::op_node(Op::Mul), Node::op_node(Op::Add), Node::constant(0.5),
             Node::op_node(Op::Add)};
  const std::vector<double> x = {0.0, 0.5, 1.0};
  const double* columns[] = {x.data()};
  std::vector<double> out(3);
  evaluate(e, columns, out);
  for (std::size_t i = 0; i < 3; ++i) {
    const double want = 0.04 + (x[i] - 0.04) * (x[i] * x[i] * (x[i] * x[i])) + 0.5;
    EXPECT_EQ(out[i], want);
    EXPECT_EQ(evaluate_scalar(e, std::vector<double>{x[i]}), want);
  }
}

// ---------------------------------------------------------------------------------------------
// Errors.

TEST(EvalErrors, Rejected) {
  Expression e = single_op(Op::Add, 0);  // x0 + x1
  const std::vector<double> x(4, 1.0);
  std::vector<double> out(4);
  const double* two[] = {x.data(), x.data()};
  const double* one[] = {x.data()};
  const double* with_null[] = {x.data(), nullptr};
  EXPECT_THROW(evaluate(e, one, out), Error);
  EXPECT_THROW(evaluate(e, with_null, out), Error);
  EXPECT_THROW(evaluate(e, two, out, {.threads = -1}), Error);
  EXPECT_THROW((void)evaluate_scalar(e, std::vector<double>{1.0}), Error);

  auto expect_malformed = [&](std::vector<Node> nodes) {
    Expression bad = e;
    bad.nodes = std::move(nodes);
    EXPECT_THROW(evaluate(bad, two, out), Error);
    EXPECT_THROW((void)evaluate_scalar(bad, std::vector<double>{1.0, 2.0}), Error);
  };
  expect_malformed({});
  expect_malformed({Node::variable(0), Node::op_node(Op::Add)});
  expect_malformed({Node::variable(0), Node::variable(1)});
  expect_malformed({Node::variable(2)});
  expect_malformed({Node::variable(-1)});
  expect_malformed({Node::parameter(0)});
  expect_malformed({Node::variable(0), Node::ipow(17)});
  expect_malformed({Node{static_cast<Op>(200), 0, 0, 0, 0.0}});
  // With zero rows the expression is still checked.
  std::vector<double> none;
  Expression bad = e;
  bad.nodes = {Node::op_node(Op::Neg)};
  EXPECT_THROW(evaluate(bad, two, std::span<double>(none)), Error);
}

}  // namespace
}  // namespace shaderfit
