#include "shaderfit/expr/print.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "expr/random_expression_test_util.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/expr/parse.hpp"

namespace shaderfit {
namespace {

ParseOptions names(std::vector<std::string> v, std::vector<std::string> params = {},
                   std::vector<double> values = {}) {
  ParseOptions o;
  o.variables = std::move(v);
  o.parameters = std::move(params);
  o.parameter_values = std::move(values);
  return o;
}

// Printed, then read back: the same value bit for bit (NaN as NaN), in float or double.
bool same_value(double a, double b) {
  return (std::isnan(a) && std::isnan(b)) ||
         std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}
bool same_value(float a, float b) {
  return (std::isnan(a) && std::isnan(b)) ||
         std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b);
}

std::string infix(const std::string& text, const PrintOptions& o = {}) {
  return to_infix(parse_formula(text, names({"a", "x", "y"})), o);
}

TEST(Print, FloatTextIsTheShortestThatReadsBackToTheSameFloat) {
  const PrintOptions people = PrintOptions::for_people();
  EXPECT_EQ(format_number(0.5829255932120166, people), "0.5829256");
  EXPECT_EQ(format_number(-9.169332193708383e-05, people), "-9.169332e-05");
  EXPECT_EQ(format_number(0.5, people), "0.5");
  EXPECT_EQ(format_number(65536.0, people), "65536");
  EXPECT_EQ(format_number(0.1, people), "0.1");
  // Beyond float's range the exact text stays (float32 would read "inf").
  EXPECT_EQ(format_number(1e300, people), "1e+300");
  EXPECT_EQ(format_number(NAN, people), "nan");
  EXPECT_EQ(format_number(-INFINITY, people), "-inf");
  // Exact is the default: the shortest text of the double.
  EXPECT_EQ(format_number(0.5829255932120166), "0.5829255932120166");
  for (double v : {0.5829255932120166, -1.6512056166817444e-11, 10430.378350446284, 1.0 / 3}) {
    const std::string s = format_number(v, people);
    EXPECT_EQ(static_cast<float>(std::strtod(s.c_str(), nullptr)), static_cast<float>(v)) << s;
    EXPECT_LE(s.size(), 15u) << s;
  }
}

TEST(Print, DigitsAreSignificantDigits) {
  const PrintOptions three = PrintOptions::for_people(3);
  EXPECT_EQ(three.numbers, NumberText::Digits);
  EXPECT_EQ(format_number(0.5829255932120166, three), "0.583");
  EXPECT_EQ(format_number(0.5, three), "0.5");
  EXPECT_EQ(format_number(-1234567.0, three), "-1.23e+06");
  EXPECT_EQ(infix("a * 0.5829255932120166 + 2", three), "0.583 * a + 2");
  EXPECT_EQ(PrintOptions::for_people(0).numbers, NumberText::Float32);
  EXPECT_TRUE(PrintOptions::for_people().substitute_parameters);
  for (int bad : {-1, 18}) {
    try {
      (void)PrintOptions::for_people(bad);
      FAIL() << bad << " digits accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.where().source, "PrintOptions::digits");
    }
  }
}

TEST(Print, ASumNeverShowsTwoSigns) {
  EXPECT_EQ(infix("a - -0.25"), "a + 0.25");
  EXPECT_EQ(infix("a + -0.25"), "a - 0.25");
  EXPECT_EQ(infix("a - -2 * x"), "a + 2 * x");
  EXPECT_EQ(infix("a + -2 * x / y"), "a - 2 * x / y");
  EXPECT_EQ(infix("a - -x"), "a + x");
  EXPECT_EQ(infix("a + -x"), "a - x");
  EXPECT_EQ(infix("a + -x * y"), "a - x * y");
  EXPECT_EQ(infix("a - -(x + y)"), "a + (x + y)");
  EXPECT_EQ(infix("a + -(x - y)"), "a - (x - y)");
  EXPECT_EQ(infix("a - -(-(2))"), "a - 2");
  EXPECT_EQ(infix("a + -2^2"), "a - 2^2");
  EXPECT_EQ(infix("a - 2^2"), "a - 2^2");
  // A negative literal factor is written first (no "* -"), its sign joining a sum's.
  EXPECT_EQ(infix("a * -2"), "-2 * a");
  EXPECT_EQ(infix("y + a * -2"), "y - 2 * a");
  EXPECT_EQ(infix("log2(3 + x * -1.75)"), "log2(3 - 1.75 * x)");
  // A negative constant first in a sum is written last.
  EXPECT_EQ(infix("-0.5 + x * y"), "x * y - 0.5");
  EXPECT_EQ(infix("a * (-0.25 + x)"), "a * (x - 0.25)");
  EXPECT_EQ(infix("-0.25 + (x - y)"), "x - y - 0.25");
  EXPECT_EQ(infix("x * -y"), "-x * y");
  EXPECT_EQ(infix("-2 * x + a"), "a - 2 * x");
  // With the constants for people too.
  EXPECT_EQ(infix("(x - -0.054242242592447185) * a", PrintOptions::for_people()),
            "(x + 0.054242242) * a");
}

TEST(Print, LatexSumsShowOneSign) {
  const ParseOptions o = names({"a", "x"}, {"k"}, {-0.5});
  auto latex = [&](const char* f) { return to_latex(parse_formula(f, o)); };
  EXPECT_EQ(latex("a - -2"), "a + 2");
  EXPECT_EQ(latex("a + -2"), "a - 2");
  EXPECT_EQ(latex("a - -x"), "a + x");
  EXPECT_EQ(latex("a + -(x - a)"), "a - \\left(x - a\\right)");
  EXPECT_EQ(to_latex(parse_formula("a - k", o), {.substitute_parameters = true}), "a + 0.5");
  EXPECT_EQ(latex("a - 2"), "a - 2");
}

TEST(Print, NegativeParametersSubstitutedKeepOneSign) {
  const ParseOptions o = names({"x"}, {"k", "m"}, {-0.5, 2.0});
  const Expression e = parse_formula("x + k - k * x + m * k", o);
  EXPECT_EQ(to_infix(e), "x + k - k * x + m * k");
  EXPECT_EQ(to_infix(e, {.substitute_parameters = true}), "x - 0.5 + 0.5 * x - 2 * 0.5");
  EXPECT_EQ(to_infix(parse_formula("x - -k", o), {.substitute_parameters = true}), "x - 0.5");
}

// Each constant of `e` replaced, half the time, by a random value of random magnitude, so that
// the printed text has long mantissas and exponents.
void scatter_constants(Rng& rng, Expression& e) {
  for (Node& n : e.nodes)
    if (n.op == Op::Const && bernoulli(rng, 0.5))
      n.value = uniform(rng, -1.0, 1.0) *
                std::pow(10.0, static_cast<double>(uniform_index(rng, 17)) - 8.0);
  for (double& v : e.parameter_values) v = uniform(rng, -3.0, 3.0);
}

TEST(Print, ExactTextReadsBackToTheSameValuesAndPrintsTheSame) {
  Rng rng(2024);
  const std::vector<std::string> vars = {"x", "y"};
  for (int i = 0; i < 6000; ++i) {
    Expression e = testing::random_expression(rng, vars, 1 + i % 6, i % 2 == 0);
    scatter_constants(rng, e);
    const std::string text = to_infix(e);
    EXPECT_EQ(text.find("- -"), std::string::npos) << text;
    EXPECT_EQ(text.find("+ -"), std::string::npos) << text;
    const ParseOptions o = names(vars, e.parameters, e.parameter_values);
    const Expression back = parse_formula(text, o);
    EXPECT_EQ(to_infix(back), text);
    // A NaN's sign bit is not kept where a sign moves (x86 keeps an operand NaN's sign): it
    // shows only through copysign, where the search never leaves a NaN.
    const bool copysign = std::any_of(e.nodes.begin(), e.nodes.end(),
                                      [](const Node& n) { return n.op == Op::CopySign; });
    for (int k = 0; k < 4; ++k) {
      const std::vector<double> at = {uniform(rng, -3.0, 3.0), uniform(rng, -3.0, 3.0)};
      bool finite = true;
      const double want = testing::eval_reference(e, at, &finite),
                   got = testing::eval_reference(back, at);
      if (copysign && !finite) continue;
      ASSERT_TRUE(same_value(want, got))
          << text << " at " << at[0] << ", " << at[1] << ": " << want << " vs " << got;
    }
  }
}

// Whether `got` equals `want` up to float rounding at a point where the formula is well
// conditioned: `exact` is its value in double, `want` in float32. Elsewhere (cancellation,
// overflow) any value passes: the order of the products may change the rounding there.
bool equal_up_to_rounding(double exact, float want, float got) {
  if (same_value(want, got)) return true;
  if (!std::isfinite(exact) || std::fabs(exact) > 1e30 || !std::isfinite(want)) return true;
  const double noise = std::fabs(static_cast<double>(want) - exact);
  if (noise > 1e-4 * std::fabs(exact)) return true;  // ill-conditioned here
  const double ulp = std::fabs(std::nextafter(want, INFINITY) - want);
  return std::fabs(static_cast<double>(got) - want) <= 16 * (noise + ulp);
}

TEST(Print, TextForPeopleReadsBackToTheSameValuesUpToFloatRounding) {
  Rng rng(77);
  const std::vector<std::string> vars = {"x", "y"};
  const PrintOptions people = PrintOptions::for_people();
  for (int i = 0; i < 6000; ++i) {
    Expression e = testing::random_expression(rng, vars, 1 + i % 6, i % 2 == 0);
    scatter_constants(rng, e);
    const std::string text = to_infix(e, people);
    for (const char* never : {"- -", "+ -", "* -", "/ -"})
      EXPECT_EQ(text.find(never), std::string::npos) << text;
    const Expression back = parse_formula(text, names(vars));
    // The constants as the text has them (float32), so that only the arithmetic differs.
    Expression rounded = e;
    for (Node& n : rounded.nodes)
      if (n.op == Op::Const) n.value = static_cast<float>(n.value);
    for (double& v : rounded.parameter_values) v = static_cast<float>(v);
    for (int k = 0; k < 4; ++k) {
      const std::vector<float> at = {static_cast<float>(uniform(rng, -3.0, 3.0)),
                                     static_cast<float>(uniform(rng, -3.0, 3.0))};
      const float want = testing::eval_reference(e, at), got = testing::eval_reference(back, at);
      const double exact =
          testing::eval_reference(rounded, std::vector<double>(at.begin(), at.end()));
      ASSERT_TRUE(equal_up_to_rounding(exact, want, got))
          << to_infix(e) << "\n  printed " << text << "\n  at " << at[0] << ", " << at[1] << ": "
          << want << " vs " << got;
    }
  }
}

TEST(Print, TextForPeopleIsWhatAPersonWrites) {
  const PrintOptions people = PrintOptions::for_people();
  const ParseOptions o = names({"x", "u", "v", "LoH", "roughness", "epsilon", "r"});
  auto text = [&](const char* f) { return to_infix(parse_formula(f, o), people); };
  // Signs: none doubled, none before a group that moving it removes.
  EXPECT_EQ(text("1.5707964 - copysign(-(1.2501888 * (-0.123236395 - x^2)), x)"),
            "1.5707964 - copysign(1.2501888 * (x^2 + 0.123236395), x)");
  EXPECT_EQ(text("log2(3 + x * -1.7724539)"), "log2(3 - 1.7724539 * x)");
  EXPECT_EQ(text("-0.2607554 * (-0.9799441 - LoH * (LoH * roughness))"),
            "0.2607554 * (LoH^2 * roughness + 0.9799441)");
  EXPECT_EQ(text("-0.13721827 - abs(x) * -0.01959862"), "0.01959862 * abs(x) - 0.13721827");
  EXPECT_EQ(text("(LoH - 0.22417034) * -roughness"), "(0.22417034 - LoH) * roughness");
  EXPECT_EQ(text("x / -2"), "-x / 2");
  EXPECT_EQ(text("-(x + u)"), "-x - u");
  EXPECT_EQ(text("-(x + u) * v"), "(-x - u) * v");
  EXPECT_EQ(text("sqrt(-(x - u))"), "sqrt(u - x)");
  EXPECT_EQ(text("abs(-x) + cos(-u)"), "abs(x) + cos(u)");
  EXPECT_EQ(text("v - sin(-u)"), "v + sin(u)");
  EXPECT_EQ(text("(-x)^3 + (-u)^2"), "u^2 - x^3");
  // Repeated factors as powers; literal factors first.
  EXPECT_EQ(text("x * x"), "x^2");
  EXPECT_EQ(text("x^2 * x + u"), "x^3 + u");
  EXPECT_EQ(text("epsilon * r * r"), "epsilon * r^2");
  EXPECT_EQ(text("x * (u * 0.5)"), "x * (0.5 * u)");  // a group may be per material
  EXPECT_EQ(text("(x + 1) * (x + 1)"), "(x + 1)^2");
  // A repeated group, also where each copy is found elsewhere (Schlick's phase function).
  EXPECT_EQ(
      text("1 - x * (1.5 - 0.5 * x * x) * (x * (1.5 - 0.5 * x * x)) + x * (1.5 - 0.5 * x * x) * u"),
      "1 - (x * (1.5 - 0.5 * x^2))^2 + x * (1.5 - 0.5 * x^2) * u");
  // exp and log where log2(e) and ln(2) appear.
  EXPECT_EQ(text("exp2(-(u * 1.4426951 * v))"), "exp(-u * v)");
  EXPECT_EQ(text("exp2(x * -1.442695)"), "exp(-x)");
  EXPECT_EQ(text("log2(x) * 0.6931472 * u"), "log(x) * u");
  EXPECT_EQ(text("exp2(1.5 * x)"), "exp2(1.5 * x)");
  // The exact text keeps the products as they are.
  EXPECT_EQ(to_infix(parse_formula("x * (u * x)", o)), "x * (u * x)");
}

TEST(Print, NeutralPartsAreNotShown) {
  const ParseOptions o = names({"x", "y"}, {"k"}, {1.0000000001});
  auto infix = [&](const char* f) { return to_infix(parse_formula(f, o)); };
  for (const char* f : {"x * 1", "1 * x", "x / 1", "x + 0", "0 + x", "x - 0", "x + -0"})
    EXPECT_EQ(infix(f), "x") << f;
  Expression power = parse_formula("y^2", o);
  power.nodes.back() = Node::ipow(1);  // x^1 does not parse; built in code, it is not shown
  power.update_lengths();
  EXPECT_EQ(to_infix(power), "y");
  EXPECT_EQ(infix("(x + y) * 1 * y"), "(x + y) * y");
  EXPECT_EQ(infix("0 - x"), "-x");
  EXPECT_EQ(infix("y - -1 * x"), "y + x");
  EXPECT_EQ(infix("x * 1.5 + 10"), "1.5 * x + 10");
  // A literal is what its text reads: k prints as 1 in float32, as itself exactly.
  const Expression e = parse_formula("x * k", o);
  EXPECT_EQ(to_infix(e, PrintOptions::for_people()), "x");
  EXPECT_EQ(to_infix(e, {.substitute_parameters = true}), "1.0000000001 * x");
  EXPECT_EQ(to_infix(e), "x * k");
  EXPECT_EQ(to_latex(parse_formula("(x + 0) * 1", o)), "x");
}

}  // namespace
}  // namespace shaderfit
