// expr/op.hpp's first derivatives against central differences of its values, and against the
// Taylor jets (expr/jet.hpp) that the same apply_* functions give, for every smooth unary and
// binary operator, at points inside each one's domain.
#include "shaderfit/expr/op.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "shaderfit/expr/jet.hpp"

namespace shaderfit {
namespace {

// d f / dx at x by a central difference with a step scaled to x.
template <typename F>
double central(F f, double x) {
  const double h = 1e-6 * std::max(1.0, std::abs(x));
  return (f(x + h) - f(x - h)) / (2 * h);
}

bool near(double got, double want, double rel) {
  return std::abs(got - want) <= rel * std::max(1.0, std::abs(want));
}

struct UnaryCase {
  Op op;
  std::vector<double> at;
};

TEST(OpDerivatives, UnaryAgreeWithDifferencesAndJets) {
  const UnaryCase cases[] = {
      {Op::Sqrt, {0.3, 2.0}},        {Op::Rsqrt, {0.3, 2.0}},       {Op::Rcp, {-2.0, 0.4}},
      {Op::Exp2, {-1.0, 2.5}},       {Op::Log2, {0.3, 7.0}},        {Op::Exp, {-1.0, 2.5}},
      {Op::Log, {0.3, 7.0}},         {Op::Sin, {-2.0, 0.7}},        {Op::Cos, {-2.0, 0.7}},
      {Op::Asin, {-0.95, 0.0, 0.6}}, {Op::Acos, {-0.95, 0.0, 0.6}}, {Op::Atan, {-7.0, 0.0, 1.3}},
      {Op::Tanh, {-3.0, 0.0, 0.8}},  {Op::Erf, {-2.5, 0.0, 0.4}},
  };
  for (const UnaryCase& c : cases) {
    for (double x : c.at) {
      const double y = apply_unary(c.op, x);
      const double d = unary_derivative(c.op, x, y);
      const double fd = central([&](double t) { return apply_unary(c.op, t); }, x);
      EXPECT_TRUE(near(d, fd, 1e-7))
          << op_info(c.op).name << "'(" << x << ") = " << d << ", differences " << fd;
      const Jet j = apply_unary(c.op, Jet::variable(x, 2));
      EXPECT_EQ(j.value(), y) << op_info(c.op).name << "(" << x << ")";
      EXPECT_TRUE(near(j.derivative(1), d, 1e-13))
          << op_info(c.op).name << "'(" << x << "): jet " << j.derivative(1) << ", op.hpp " << d;
    }
  }
}

TEST(OpDerivatives, BinaryAgreeWithDifferencesAndJets) {
  struct BinaryCase {
    Op op;
    double a, b;
  };
  const BinaryCase cases[] = {
      {Op::Mul, 1.5, -2.0},   {Op::Div, 1.5, -2.0},    {Op::Pow, 1.7, 0.6},
      {Op::Atan2, 0.3, 2.0},  {Op::Atan2, -1.2, -0.4}, {Op::Atan2, 2.0, -3.0},
      {Op::Atan2, -0.5, 0.0},
  };
  for (const BinaryCase& c : cases) {
    const double y = apply_binary(c.op, c.a, c.b);
    const BinaryPartials<double> p = binary_partials(c.op, c.a, c.b, y);
    const double da = central([&](double t) { return apply_binary(c.op, t, c.b); }, c.a);
    const double db = central([&](double t) { return apply_binary(c.op, c.a, t); }, c.b);
    EXPECT_TRUE(near(p.da, da, 1e-7)) << op_info(c.op).name << " d/da at " << c.a << ", " << c.b;
    EXPECT_TRUE(near(p.db, db, 1e-7)) << op_info(c.op).name << " d/db at " << c.a << ", " << c.b;
    const Jet ja = apply_binary(c.op, Jet::variable(c.a, 1), Jet(c.b));
    const Jet jb = apply_binary(c.op, Jet(c.a), Jet::variable(c.b, 1));
    EXPECT_TRUE(near(ja.derivative(1), p.da, 1e-13)) << op_info(c.op).name;
    EXPECT_TRUE(near(jb.derivative(1), p.db, 1e-13)) << op_info(c.op).name;
  }
}

TEST(OpDerivatives, EdgesOfTheDomains) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  // asin and acos: infinite slope at +-1, none outside.
  EXPECT_EQ(unary_derivative(Op::Asin, 1.0, apply_unary(Op::Asin, 1.0)), inf);
  EXPECT_EQ(unary_derivative(Op::Acos, -1.0, apply_unary(Op::Acos, -1.0)), -inf);
  EXPECT_TRUE(std::isnan(unary_derivative(Op::Asin, 1.5, apply_unary(Op::Asin, 1.5))));
  EXPECT_TRUE(std::isnan(apply_unary(Op::Acos, -1.5)));
  // tanh and erf flatten out; atan2's partials vanish far away and are undefined at the origin.
  EXPECT_EQ(unary_derivative(Op::Tanh, 40.0, apply_unary(Op::Tanh, 40.0)), 0.0);
  EXPECT_EQ(unary_derivative(Op::Erf, -40.0, apply_unary(Op::Erf, -40.0)), 0.0);
  EXPECT_TRUE(std::isnan(binary_partials(Op::Atan2, 0.0, 0.0, 0.0).da));
  // The names read back.
  for (Op op : {Op::Asin, Op::Acos, Op::Atan, Op::Atan2, Op::Tanh, Op::Erf})
    EXPECT_EQ(op_from_name(op_info(op).name), op);
  EXPECT_EQ(arity(Op::Atan2), 2);
  EXPECT_EQ(arity(Op::Erf), 1);
}

}  // namespace
}  // namespace shaderfit
