#include "shaderfit/expr/parse.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "expr/random_expression_test_util.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/expr/forward.hpp"
#include "shaderfit/expr/print.hpp"

namespace shaderfit {
namespace {

ParseOptions vars(std::vector<std::string> v) {
  ParseOptions o;
  o.variables = std::move(v);
  return o;
}

TEST(Parse, SeedFormulaPostfix) {
  Expression e = parse_formula("r0 + (x - r0) * x^4", vars({"r0", "x"}));
  ASSERT_EQ(e.size(), 8u);
  EXPECT_EQ(e.nodes[0].op, Op::Var);
  EXPECT_EQ(e.nodes[5].op, Op::IPow);
  EXPECT_EQ(e.nodes[5].index, 4);
  EXPECT_EQ(e.nodes.back().op, Op::Add);
  EXPECT_EQ(e.nodes.back().length, 7u);
  EXPECT_EQ(to_infix(e), "r0 + (x - r0) * x^4");
}

TEST(Parse, LiteralsAsParameters) {
  ParseOptions o = vars({"r0", "x", "p0"});
  o.parameters = {"k"};
  o.parameter_values = {3.0};
  o.literals_as_parameters = true;
  const Expression e = parse_formula("k * r0 + (1 - r0) * x^5 * pow(x, 2) + -0.5 * pi * p0", o);
  // 1 and -0.5 are free (named around the variable p0); pi and the exponents stay exact.
  EXPECT_EQ(e.parameters, (std::vector<std::string>{"k", "p1", "p2"}));
  EXPECT_EQ(e.parameter_values, (std::vector<double>{3.0, 1.0, -0.5}));
  int constants = 0, powers = 0;
  for (const Node& n : e.nodes) {
    constants += n.op == Op::Const ? 1 : 0;
    powers += n.op == Op::IPow ? 1 : 0;
  }
  EXPECT_EQ(constants, 1);  // pi
  EXPECT_EQ(powers, 2);
  EXPECT_EQ(to_infix(e, {.substitute_parameters = true}),
            to_infix(parse_formula("3 * r0 + (1 - r0) * x^5 * x^2 + -0.5 * pi * p0",
                                   vars({"r0", "x", "p0"})),
                     {}));
}

TEST(Parse, PowWithIntegerLiteralIsIntegerPower) {
  Expression e = parse_formula("pow(x, 5)", vars({"x"}));
  ASSERT_EQ(e.size(), 2u);
  EXPECT_EQ(e.nodes[1].op, Op::IPow);
  EXPECT_EQ(e.nodes[1].index, 5);
  Expression r = parse_formula("pow(x, 2.5)", vars({"x"}));
  EXPECT_EQ(r.nodes.back().op, Op::Pow);
  Expression neg = parse_formula("pow(x, -2)", vars({"x"}));
  EXPECT_EQ(neg.nodes.back().op, Op::IPow);
  EXPECT_EQ(neg.nodes.back().index, -2);
}

TEST(Parse, PowersOneAndZeroAreTheBaseAndOne) {
  EXPECT_EQ(to_infix(parse_formula("x^1 + 2", vars({"x"}))), "x + 2");
  const Expression zero = parse_formula("(x + 3)^0 * x", vars({"x"}));  // 1 * x
  ASSERT_EQ(zero.size(), 3u);
  EXPECT_EQ(zero.nodes[0].op, Op::Const);
  EXPECT_EQ(zero.nodes[0].value, 1.0);
  EXPECT_EQ(parse_formula("2 * sqrt(x)^-0", vars({"x"})).size(), 3u);  // 2 * 1
}

TEST(Parse, PrecedenceAndUnaryMinus) {
  auto p = [](const char* s) { return to_infix(parse_formula(s, vars({"x", "y", "cos_theta"}))); };
  EXPECT_EQ(p("1 - cos_theta"), "1 - cos_theta");
  EXPECT_EQ(p("-x^2"), "-x^2");
  EXPECT_EQ(p("(-x)^2"), "x^2");
  EXPECT_EQ(p("-2^2"), "-2^2");
  EXPECT_EQ(p("x - (y - 1)"), "x - (y - 1)");
  EXPECT_EQ(p("(x - y) - 1"), "x - y - 1");
  EXPECT_EQ(p("x / (y * 2)"), "x / (2 * y)");
  EXPECT_EQ(p("x^2^3"), "(x^2)^3");
  EXPECT_EQ(p("2.5e-3 * x"), "0.0025 * x");
  EXPECT_EQ(p("x * -2"), "-2 * x");
  EXPECT_EQ(p("-(2)"), "-2");
  EXPECT_EQ(p("fma(x, y, 1)"), "fma(x, y, 1)");
  EXPECT_EQ(p("inversesqrt(x)"), "rsqrt(x)");
  Expression neg = parse_formula("-0.5", vars({}));
  ASSERT_EQ(neg.size(), 1u);
  EXPECT_EQ(neg.nodes[0].value, -0.5);
}

TEST(Parse, ParametersAndFreeVariables) {
  ParseOptions o;
  o.parameters = {"s"};
  o.parameter_values = {0.25};
  Expression e = parse_formula("r0 + (1 - r0 - s * cos_theta) * (1 - cos_theta)^4", o);
  EXPECT_EQ(e.variables, (std::vector<std::string>{"r0", "cos_theta"}));
  ASSERT_EQ(e.parameters.size(), 1u);
  EXPECT_EQ(e.parameter_values[0], 0.25);
  EXPECT_NE(to_infix(e).find("s * cos_theta"), std::string::npos);
  PrintOptions sub;
  sub.substitute_parameters = true;
  EXPECT_NE(to_infix(e, sub).find("0.25 * cos_theta"), std::string::npos);
}

// Each bad formula, the message it must contain, and the column it must point at.
struct BadFormula {
  const char* text;
  const char* message;
  int column;
};

void PrintTo(const BadFormula& b, std::ostream* os) { *os << '"' << b.text << '"'; }

class ParseErrors : public ::testing::TestWithParam<BadFormula> {};

TEST_P(ParseErrors, NamesTheProblemAndColumn) {
  const BadFormula& b = GetParam();
  try {
    parse_formula(b.text, vars({"x", "r0"}));
    FAIL() << "no error for " << b.text;
  } catch (const Error& e) {
    EXPECT_NE(e.message().find(b.message), std::string::npos) << e.what();
    EXPECT_EQ(e.where().source, "formula");
    EXPECT_EQ(e.where().line, 1);
    EXPECT_EQ(e.where().column, b.column) << e.what();
  }
}

INSTANTIATE_TEST_SUITE_P(
    All, ParseErrors,
    ::testing::Values(
        BadFormula{"x +", "operand is missing", 4}, BadFormula{"r0 + (x - r0", "expected ')'", 13},
        BadFormula{"x + y", "unknown variable 'y' (known: x, r0)", 5},
        BadFormula{"foo(x)", "unknown function 'foo'", 1},
        BadFormula{"sqrt(x, x)", "sqrt takes 1 argument, got 2", 1},
        BadFormula{"x ^ 2.5", "integer literal", 5}, BadFormula{"x^17", "out of range", 3},
        BadFormula{"x ^ -17", "out of range", 5}, BadFormula{"", "empty formula", 1},
        BadFormula{"x $ 2", "unexpected character '$'", 3}, BadFormula{"x )", "unexpected ')'", 3},
        BadFormula{"()", "empty parentheses", 1}, BadFormula{"2x", "after the number", 2},
        BadFormula{"1e+", "exponent has no digits", 1}, BadFormula{"sqrt", "needs arguments", 1},
        BadFormula{"1e999", "out of range", 1},
        BadFormula{"min(x)", "min takes 2 arguments, got 1", 1},
        BadFormula{"x >= 0", "only allowed in a condition", 3},
        BadFormula{"sqrt(x < r0)", "only allowed in a condition", 8},
        BadFormula{"select(x, 1, 2)", "must be a comparison", 8},
        BadFormula{"select(x + 1 = 0, 1, 2)", "unexpected character '='", 14},
        BadFormula{"select(x >= 0, 1 < x, 2)", "only allowed in a condition", 18},
        BadFormula{"select(x >= r0 >= 0, 1, 2)", "only allowed in a condition", 16},
        BadFormula{"select((x >= 0) + 1, 1, 2)", "only allowed in a condition", 11},
        BadFormula{"(x > 0) + 1 ? 1 : 2", "only allowed in a condition", 4},
        BadFormula{"max((x > 0), 1)", "only allowed in a condition", 8},
        BadFormula{"select(x >= 0, 1)", "expected ',' and two more", 17},
        BadFormula{"select(x >= 0, 1, 2, 3)", "expected ')' after the 3", 20},
        BadFormula{"select()", "select takes 3 arguments, got 0", 1},
        BadFormula{"x ? 1 : 2", "the condition before '?' must be a comparison", 3},
        BadFormula{"x > 1 ? 2", "expected ':' after the first branch of '?' at column 7", 10},
        BadFormula{"x > 1 > 2 ? 1 : 2", "comparisons do not chain", 7},
        BadFormula{"x : 2", "unexpected ':' without a '?'", 3},
        BadFormula{"copysign(x)", "copysign takes 2 arguments, got 1", 1},
        BadFormula{"sign(x, r0)", "sign takes 1 argument, got 2", 1}),
    [](const ::testing::TestParamInfo<BadFormula>& p) { return "case" + std::to_string(p.index); });

TEST(Parse, SignAndCopySign) {
  auto p = [](const char* s) { return to_infix(parse_formula(s, vars({"x", "y"}))); };
  EXPECT_EQ(p("sign(x - 1)"), "sign(x - 1)");
  EXPECT_EQ(p("copysign(x, -y)"), "copysign(x, -y)");
  EXPECT_EQ(parse_formula("copysign(1, x)", vars({"x"})).nodes.back().op, Op::CopySign);
  EXPECT_EQ(parse_formula("sign(x)", vars({"x"})).nodes.back().op, Op::Sign);
}

TEST(Parse, InverseTrigonometricTanhErf) {
  auto p = [](const char* s) { return to_infix(parse_formula(s, vars({"x", "y"}))); };
  EXPECT_EQ(p("asin(x) + acos(y) * atan(x / y)"), "asin(x) + acos(y) * atan(x / y)");
  EXPECT_EQ(p("atan2(y, x) - tanh(-x) * erf(2 * y)"), "atan2(y, x) - tanh(-x) * erf(2 * y)");
  // GLSL's two-argument atan is atan2.
  const Expression e = parse_formula("atan(y, x)", vars({"x", "y"}));
  EXPECT_EQ(e.nodes.back().op, Op::Atan2);
  EXPECT_EQ(to_infix(e), "atan2(y, x)");
  EXPECT_THROW(parse_formula("atan(x, y, x)", vars({"x", "y"})), Error);
  EXPECT_THROW(parse_formula("erf(x, y)", vars({"x", "y"})), Error);
  EXPECT_THROW(parse_formula("tanh", vars({"x"})), Error);  // a function, not a variable
  EXPECT_EQ(to_latex(parse_formula("asin(x) + acos(x) + atan(x) + tanh(x) + erf(x)", vars({"x"}))),
            "\\arcsin\\left(x\\right) + \\arccos\\left(x\\right) + \\arctan\\left(x\\right) + "
            "\\tanh\\left(x\\right) + \\operatorname{erf}\\left(x\\right)");
  EXPECT_EQ(to_latex(parse_formula("atan2(y, x)", vars({"x", "y"}))),
            "\\operatorname{atan2}\\left(y, x\\right)");
  // Their values are C's.
  const double row[] = {0.3, -0.7};
  EXPECT_EQ(evaluate_at<double>(parse_formula("atan(y, x)", vars({"x", "y"})),
                                std::span<const double>(row), {}),
            std::atan2(-0.7, 0.3));
  EXPECT_EQ(evaluate_at<double>(parse_formula("erf(x) - asin(y)", vars({"x", "y"})),
                                std::span<const double>(row), {}),
            std::erf(0.3) - std::asin(-0.7));
}

// Each comparison is lowered to select(a, b, c) = a >= 0 ? b : c on a difference, as the parser
// documents; the printer writes the operand back as "a >= 0".
TEST(Parse, SelectComparisonsLowerToOneOperator) {
  auto p = [](const char* s) { return to_infix(parse_formula(s, vars({"x", "y"}))); };
  EXPECT_EQ(p("select(x >= y, 1, 2)"), "select(x - y >= 0, 1, 2)");
  EXPECT_EQ(p("select(x <= y, 1, 2)"), "select(y - x >= 0, 1, 2)");
  EXPECT_EQ(p("select(x > y, 1, 2)"), "select(y - x >= 0, 2, 1)");
  EXPECT_EQ(p("select(x < y, 1, 2)"), "select(x - y >= 0, 2, 1)");
  // A literal zero side adds no node: x, or -x.
  EXPECT_EQ(p("select(x >= 0, y, 2)"), "select(x >= 0, y, 2)");
  EXPECT_EQ(p("select(x > 0, y, 2)"), "select(-x >= 0, 2, y)");
  EXPECT_EQ(p("select(0 <= x * y, y, 2)"), "select(x * y >= 0, y, 2)");
  EXPECT_EQ(p("select(0 < x, y, 2)"), "select(-x >= 0, 2, y)");
  EXPECT_EQ(p("select(x < 0.0, y, 2)"), "select(x >= 0, 2, y)");
  EXPECT_EQ(p("select(x + 1 >= y * 2, min(x, y), sqrt(y))"),
            "select(x + 1 - 2 * y >= 0, min(x, y), sqrt(y))");
  const Expression e = parse_formula("select(x >= y, x, y)", vars({"x", "y"}));
  ASSERT_EQ(e.size(), 6u);
  EXPECT_EQ(e.nodes[2].op, Op::Sub);
  EXPECT_EQ(e.nodes.back().op, Op::Select);
  // The swapped forms agree with the comparison they were written as (away from NaN).
  for (const char* cmp : {">=", ">", "<=", "<"}) {
    const Expression s =
        parse_formula("select(x " + std::string(cmp) + " y, 1, 2)", vars({"x", "y"}));
    for (double x : {-1.0, 0.0, 0.5, 2.0})
      for (double y : {-1.0, 0.0, 0.5}) {
        const bool holds =
            cmp[0] == '>' ? (cmp[1] == '=' ? x >= y : x > y) : (cmp[1] == '=' ? x <= y : x < y);
        const double row[] = {x, y};
        EXPECT_EQ(evaluate_at<double>(s, std::span<const double>(row), {}), holds ? 1.0 : 2.0)
            << cmp << " " << x << " " << y;
      }
  }
  // pi and parameters next to a comparison keep their places.
  ParseOptions o = vars({"x"});
  o.literals_as_parameters = true;
  const Expression q = parse_formula("select(pi > x, 0.5, 3)", o);
  EXPECT_EQ(to_infix(q, {.substitute_parameters = true}),
            "select(x - 3.141592653589793 >= 0, 3, 0.5)");
}

// C's conditional is select: X cmp Y ? b : c parses to select(X cmp Y, b, c), lowest in
// precedence and nesting to the right.
TEST(Parse, ConditionalIsSelect) {
  auto p = [](const char* s) { return to_infix(parse_formula(s, vars({"x", "y"}))); };
  EXPECT_EQ(p("x > 0.5 ? x*x : sqrt(x)"), p("select(x > 0.5, x*x, sqrt(x))"));
  EXPECT_EQ(p("x >= y ? 1 : 2"), "select(x - y >= 0, 1, 2)");
  EXPECT_EQ(p("x < y ? 1 : x > 2 ? 3 : 4"), p("select(x < y, 1, select(x > 2, 3, 4))"));
  EXPECT_EQ(p("1 + (x <= y ? x : y) * 2"), p("1 + select(x <= y, x, y) * 2"));
  EXPECT_EQ(p("x + 1 >= y * 2 ? x : y + 1"), p("select(x + 1 >= y * 2, x, y + 1)"));
  // A parenthesized comparison, as C code writes it.
  EXPECT_EQ(p("(x > 0.5) ? x*x : sqrt(x)"), p("select(x > 0.5, x*x, sqrt(x))"));
  EXPECT_EQ(p("((x >= y)) ? 1 : 2"), "select(x - y >= 0, 1, 2)");
  EXPECT_EQ(p("select((x >= y), 1, 2)"), "select(x - y >= 0, 1, 2)");
  EXPECT_EQ(p("x > 0 ? (y > 0) ? 1 : 2 : 3"), p("select(x > 0, select(y > 0, 1, 2), 3)"));
}

TEST(Parse, PrintThenParseRoundTripsRandomExpressions) {
  Rng rng(12345);
  const std::vector<std::string> names = {"x", "r0", "cos_theta"};
  int checked = 0;
  for (int i = 0; i < 12000; ++i) {
    Expression e = testing::random_expression(rng, names, 1 + static_cast<int>(i % 7), i % 3 == 0);
    const std::string text = to_infix(e);
    ParseOptions o;
    o.variables = names;
    o.parameters = e.parameters;
    o.parameter_values = e.parameter_values;
    Expression back;
    ASSERT_NO_THROW(back = parse_formula(text, o)) << text;
    // The printer folds a sign into a sum (a - -c is printed a + c, the same value: print_test),
    // so what it reads back prints the same and reads back node for node.
    ASSERT_EQ(to_infix(back), text);
    const Expression again = parse_formula(to_infix(back), o);
    ASSERT_TRUE(again == back) << text;
    EXPECT_EQ(structural_hash(again), structural_hash(back));
    ++checked;
  }
  EXPECT_GE(checked, 10000);
}

// Limits that keep recursive consumers within the stack (fuzz/regressions/formula has the inputs
// that overflowed it before).
TEST(Parse, SizeLimitsAreErrorsWithAColumn) {
  auto nested = [](int levels) {
    return std::string(static_cast<std::size_t>(levels) - 1, '(') + "x" +
           std::string(static_cast<std::size_t>(levels) - 1, ')');
  };
  EXPECT_NO_THROW(parse_formula(nested(kMaxFormulaNesting), vars({"x"})));
  try {
    parse_formula(nested(kMaxFormulaNesting + 1), vars({"x"}));
    FAIL() << "nesting beyond the limit parsed";
  } catch (const Error& e) {
    EXPECT_NE(e.message().find("nested more than 256 levels"), std::string::npos) << e.what();
    EXPECT_EQ(e.where().column, kMaxFormulaNesting + 1);
  }
  EXPECT_THROW(parse_formula(std::string(300, '-') + "x", vars({"x"})), Error);
  auto sum = [](int terms) {
    std::string s = "x";
    for (int i = 1; i < terms; ++i) s += "+x";
    return s;
  };
  EXPECT_NO_THROW(parse_formula(sum(kMaxFormulaDepth), vars({"x"})));
  try {
    parse_formula(sum(kMaxFormulaDepth + 1), vars({"x"}));
    FAIL() << "a tree deeper than the limit parsed";
  } catch (const Error& e) {
    EXPECT_NE(e.message().find("formula too deep"), std::string::npos) << e.what();
  }
}

TEST(Print, Latex) {
  Expression e = parse_formula("r0 + (x - r0) * x^4", vars({"r0", "x"}));
  EXPECT_EQ(to_latex(e), "r_{0} + \\left(x - r_{0}\\right) \\cdot x^{4}");
  Expression f = parse_formula("sqrt(x) / exp2(-x) + 1e-6", vars({"x"}));
  EXPECT_EQ(to_latex(f), "\\frac{\\sqrt{x}}{2^{-x}} + 1 \\times 10^{-06}");
  Expression g = parse_formula("cos_theta", {});
  EXPECT_EQ(to_latex(g), "\\mathrm{cos\\_theta}");
}

TEST(Hash, CommutativeOperandsHashAlike) {
  auto h = [](const char* s) { return structural_hash(parse_formula(s, vars({"x", "y"}))); };
  EXPECT_EQ(h("x + y"), h("y + x"));
  EXPECT_EQ(h("x * (y + 1)"), h("(1 + y) * x"));
  EXPECT_NE(h("x - y"), h("y - x"));
  EXPECT_NE(h("x^2"), h("x^3"));
  EXPECT_NE(h("x"), h("y"));
}

TEST(Names, GeneratedValuesTakeAPrefixNoInputOrParameterHas) {
  EXPECT_EQ(unused_name_prefix(parse_formula("x + y", vars({"x", "y"})), 't'), "t");
  // "t", "t1x", "_t" and "t_1" are not the prefix followed by digits; "t1" is.
  EXPECT_EQ(unused_name_prefix(parse_formula("t + t1x + _t + t_1", vars({"t", "t1x", "_t", "t_1"})),
                               't'),
            "t");
  EXPECT_EQ(unused_name_prefix(parse_formula("t1 + m", vars({"t1", "m"})), 't'), "_t");
  EXPECT_EQ(unused_name_prefix(parse_formula("t1 + _t20", vars({"t1", "_t20"})), 't'), "__t");
  EXPECT_EQ(unused_name_prefix(parse_formula("t1 + x", vars({"t1", "x"})), 'm'), "m");
  Expression e = parse_formula("x + 1", vars({"x"}));
  e.parameters = {"m0"};
  EXPECT_EQ(unused_name_prefix(e, 'm'), "_m");
}

}  // namespace
}  // namespace shaderfit
