#include "shaderfit/reference/program.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <set>

#include "shaderfit/core/error.hpp"
#include "shaderfit/expr/jet.hpp"
#include "shaderfit/reference/language.hpp"
#include "shaderfit/reference/program_evaluate.hpp"

namespace shaderfit::reference {
namespace {

Program compile(const std::string& formula, std::vector<std::string> variables) {
  ReferenceText t;
  t.formula = formula;
  t.variables = std::move(variables);
  return compile_reference(t);
}

TEST(ProgramOps, EachOpHasANameAndAnArity) {
  std::set<std::string_view> names;
  for (int i = 0; i < kProgramOpCount; ++i) {
    const auto op = static_cast<ProgramOp>(i);
    EXPECT_TRUE(names.insert(program_op_name(op)).second) << program_op_name(op);
    EXPECT_LE(program_op_arity(op), kMaxProgramOperands);
  }
  EXPECT_EQ(program_op_name(ProgramOp::Cbrt), "cbrt");
  EXPECT_EQ(program_op_name(ProgramOp::LessEqual), "<=");
  EXPECT_EQ(program_op_arity(ProgramOp::Select), 3);
  EXPECT_EQ(program_op_arity(ProgramOp::Hypot), 2);
  EXPECT_EQ(program_op_arity(ProgramOp::Operator), -1);
  EXPECT_EQ(program_op_arity(ProgramOp::Input), 0);
  EXPECT_EQ(program_op_arity(ProgramOp::Builtin), -1);
}

// A program written by hand: y = x0 < x1 ? x0^-2 : hypot(x0, x1), the outputs y and x1.
TEST(Program, EvaluatesHandWrittenCode) {
  Program p;
  p.inputs = {"a", "b"};
  auto add = [&](ProgramOp op, std::initializer_list<std::uint32_t> operands, int index = 0,
                 double value = 0) {
    Instruction in;
    in.op = op;
    in.index = index;
    in.value = value;
    in.arity = static_cast<std::uint8_t>(operands.size());
    std::size_t k = 0;
    for (const std::uint32_t r : operands) in.operands[k++] = r;
    p.code.push_back(in);
    return static_cast<std::uint32_t>(p.code.size() - 1);
  };
  const auto a = add(ProgramOp::Input, {}, 0), b = add(ProgramOp::Input, {}, 1);
  const auto less = add(ProgramOp::Less, {a, b});
  const auto power = add(ProgramOp::IPow, {a}, -2);
  const auto h = add(ProgramOp::Hypot, {a, b});
  const auto y = add(ProgramOp::Select, {less, power, h});
  p.outputs = {b, y};
  p.output_names = {"b", "y"};
  EXPECT_EQ(p.evaluate(std::vector<double>{0.5, 2.0}), 4.0);
  EXPECT_EQ(p.evaluate(std::vector<double>{3.0, 4.0}), 0x1.c71c71c71c71cp-4);  // 1/9
  EXPECT_EQ(p.evaluate(std::vector<double>{4.0, 3.0}), 5.0);
  std::vector<double> all(2);
  p.evaluate_all(std::vector<double>{4.0, 3.0}, all);
  EXPECT_EQ(all, (std::vector<double>{3.0, 5.0}));
  EXPECT_EQ(p.find_output("y"), 1);
  EXPECT_EQ(p.find_output("a"), -1);
  EXPECT_EQ(p.find_input("b"), 1);
  EXPECT_EQ(p.find_input("y"), -1);
}

TEST(Program, WrongCountsAreErrors) {
  const Program p = compile("x * y", {"x", "y"});
  EXPECT_THROW((void)p.evaluate(std::vector<double>{1.0}), Error);
  std::vector<double> out(2);
  EXPECT_THROW(p.evaluate_all(std::vector<double>{1.0, 2.0}, out), Error);
  const std::vector<double> x = {1, 2, 3}, y = {1, 2};
  const std::span<const double> columns[] = {x, y};
  EXPECT_THROW((void)p.evaluate_columns(columns), Error);
  try {
    (void)p.evaluate(std::vector<double>{1.0, 2.0, 3.0});
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.message(), "the reference takes 2 inputs, got 3");
  }
}

TEST(Program, ColumnsGiveEveryOutputAtEveryRow) {
  ReferenceText t;
  t.formula = "acos(x) * k";
  t.variables = {"x"};
  t.definitions = {"k = 2"};
  const Program p = compile_reference(t);
  std::vector<double> x(100001);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = -1.0 + 2.0 * static_cast<double>(i) / 100000;
  const std::span<const double> columns[] = {x};
  const std::vector<std::vector<double>> out = p.evaluate_columns(columns);
  ASSERT_EQ(out.size(), 3u);  // x, k, reference
  for (std::size_t i = 0; i < x.size(); i += 997) {
    EXPECT_EQ(out[0][i], x[i]);
    EXPECT_EQ(out[1][i], 2.0);
    EXPECT_EQ(out[2][i], std::acos(x[i]) * 2.0);
  }
  EXPECT_EQ(out[2].back(), 0.0);
}

// evaluate_program<Jet>: derivatives of every order, exact to rounding, through comparisons,
// selects, the C functions and a built-in reference.
TEST(ProgramJets, DerivativesAreExact) {
  const Program p = compile("x < 0.5 ? acos(x) + erf(2 * x) : atan2(x, 1 - x) * tanh(x)^2", {"x"});
  for (const double x : {0.2, 0.7}) {
    const Jet in[] = {Jet::variable(x, 3)};
    std::vector<Jet> regs;
    evaluate_program<Jet>(p, in, regs);
    const Jet& y = regs[p.outputs.back()];
    double d1 = 0, d2 = 0, value = 0;
    if (x < 0.5) {
      // acos' = -1 / sqrt(1 - x^2), erf(2x)' = 4 / sqrt(pi) exp(-4x^2).
      const double s = std::sqrt(1 - x * x),
                   g = std::exp(-4 * x * x) * 4 / std::sqrt(std::numbers::pi);
      value = std::acos(x) + std::erf(2 * x);
      d1 = -1 / s + g;
      d2 = -x / (s * s * s) + g * (-8 * x);
    } else {
      // atan2(x, 1 - x)' = 1 / (x^2 + (1 - x)^2); (tanh^2)' = 2 tanh (1 - tanh^2).
      const double q = x * x + (1 - x) * (1 - x), th = std::tanh(x), u = 1 - th * th;
      const double a = std::atan2(x, 1 - x), da = 1 / q, dda = -(4 * x - 2) / (q * q);
      const double t = th * th, dt = 2 * th * u, ddt = 2 * u * u - 4 * th * th * u;
      value = a * t;
      d1 = da * t + a * dt;
      d2 = dda * t + 2 * da * dt + a * ddt;
    }
    EXPECT_EQ(y.value(), p.evaluate(std::vector<double>{x}));
    EXPECT_NEAR(y.value(), value, 1e-15);
    EXPECT_NEAR(y.derivative(1), d1, 1e-13) << x;
    EXPECT_NEAR(y.derivative(2), d2, 1e-12) << x;
  }
  // A built-in reference by name: Schlick's Fresnel, F0 + (1 - F0) (1 - c)^5.
  const Program s = compile("fresnel_schlick(c, 0.04)", {"c"});
  const Jet in[] = {Jet::variable(0.3, 2)};
  std::vector<Jet> regs;
  evaluate_program<Jet>(s, in, regs);
  EXPECT_NEAR(regs[s.outputs.back()].derivative(1), -5 * 0.96 * std::pow(0.7, 4), 1e-15);
}

// Every function of the formula language on jets: the value is the double program's, the first
// derivative a central difference's.
TEST(ProgramJets, EveryFunctionHasItsDerivative) {
  const char* formulas[] = {
      "abs(x - 1)",
      "sign(x) * x",
      "sqrt(x)",
      "cbrt(x)",
      "exp(x)",
      "exp2(x)",
      "expm1(x)",
      "log(x)",
      "log2(x)",
      "log10(x)",
      "log1p(x)",
      "sin(x)",
      "cos(x)",
      "tan(x)",
      "asin(x / 2)",
      "acos(x / 2)",
      "atan(x)",
      "atan2(x, 1 - x)",
      "sinh(x)",
      "cosh(x)",
      "tanh(x)",
      "asinh(x)",
      "acosh(x + 1)",
      "atanh(x / 2)",
      "erf(x)",
      "erfc(x)",
      "floor(x) + x",
      "ceil(x) * x",
      "trunc(x) + x",
      "round(x) - x",
      "pow(x, 2.4)",
      "pow(2.4, x)",
      "x^2.5",
      "x^-3",
      "hypot(x, 0.5)",
      "fmod(3 * x, 0.4)",
      "min(x, 0.6)",
      "max(x, 0.6)",
      "fmin(x, 0.6)",
      "copysign(x, -1)",
      "clamp(x, 0, 0.5)",
      "saturate(2 * x)",
      "rsqrt(x)",
      "rcp(x)",
      "fma(x, x, 1)",
      "x < 0.5 ? x : x * x",
      "select(x >= 0.5, 1 / x, x)",
      "(x > 0.2 && x < 0.9) * x",
      "ggx_d(x, 0.5)",
      "fresnel_dielectric(x, 1.5)",
  };
  for (const char* formula : formulas) {
    const Program p = compile(formula, {"x"});
    for (const double x : {0.3, 0.7}) {
      const Jet in[] = {Jet::variable(x, 2)};
      std::vector<Jet> regs;
      evaluate_program<Jet>(p, in, regs);
      const Jet& y = regs[p.outputs.back()];
      auto f = [&](double v) { return p.evaluate(std::vector<double>{v}); };
      const double h = 1e-6;
      EXPECT_EQ(y.value(), f(x)) << formula << " at " << x;
      EXPECT_NEAR(y.derivative(1), (f(x + h) - f(x - h)) / (2 * h),
                  1e-6 * std::max(1.0, std::abs(y.derivative(1))))
          << formula << " at " << x;
    }
  }
}

}  // namespace
}  // namespace shaderfit::reference
