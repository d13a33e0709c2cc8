// The formula side of the reference language (reference/language.hpp): a superset of the
// approximation's syntax (expr/parse.hpp), the C math library, the built-in references,
// definitions, and its errors.
#include "shaderfit/reference/language.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "expr/random_expression_test_util.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/expr/print.hpp"
#include "shaderfit/reference/builtin.hpp"
#include "shaderfit/reference/fresnel.hpp"

namespace shaderfit::reference {
namespace {

Program compile(const std::string& formula, std::vector<std::string> variables = {},
                std::vector<std::string> definitions = {}) {
  ReferenceText t;
  t.formula = formula;
  t.variables = std::move(variables);
  t.definitions = std::move(definitions);
  return compile_reference(t);
}

double at(const Program& p, std::vector<double> point) { return p.evaluate(point); }

// The error compile_reference throws for the formula, or a failure.
Error error_of(const std::string& formula, std::vector<std::string> variables = {},
               std::vector<std::string> definitions = {}) {
  try {
    (void)compile(formula, std::move(variables), std::move(definitions));
  } catch (const Error& e) {
    return e;
  }
  ADD_FAILURE() << "'" << formula << "' compiled";
  return Error("");
}

// The approximation's meaning of an expression with pow read as C's pow (the one place the
// reference language differs: expr/op.hpp computes pow as exp2(b log2 a)); `finite` is cleared
// when an intermediate value is NaN or infinite.
double approximation_value(const Expression& e, const std::vector<double>& vars, bool& finite) {
  std::vector<double> st;
  for (const Node& n : e.nodes) {
    if (n.op == Op::Const) {
      st.push_back(n.value);
      continue;
    }
    if (n.op == Op::Var) {
      st.push_back(vars[static_cast<std::size_t>(n.index)]);
      continue;
    }
    double r = 0;
    if (n.arity == 1) {
      r = n.op == Op::IPow ? apply_ipow(st.back(), n.index) : apply_unary(n.op, st.back());
      st.pop_back();
    } else if (n.arity == 2) {
      const double b = st.back();
      st.pop_back();
      const double a = st.back();
      st.pop_back();
      r = n.op == Op::Pow ? std::pow(a, b) : apply_binary(n.op, a, b);
    } else {
      const double c = st.back();
      st.pop_back();
      const double b = st.back();
      st.pop_back();
      const double a = st.back();
      st.pop_back();
      r = apply_ternary(n.op, a, b, c);
    }
    finite = finite && std::isfinite(r);
    st.push_back(r);
  }
  return st.back();
}

bool same(double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); }

TEST(ReferenceFormula, EveryApproximationFormulaMeansTheSame) {
  Rng rng(2600);
  const std::vector<std::string> vars = {"x", "r0", "cos_theta"};
  int compared = 0;
  for (int i = 0; i < 6000; ++i) {
    const Expression e = testing::random_expression(rng, vars, 1 + i % 7);
    const std::string text = to_infix(e);
    ParseOptions o;
    o.variables = vars;
    const Expression approx = parse_formula(text, o);
    Program p;
    ASSERT_NO_THROW(p = compile(text, vars)) << text;
    for (int k = 0; k < 4; ++k) {
      const std::vector<double> point = {uniform(rng, -3.0, 3.0), uniform(rng, -3.0, 3.0),
                                         uniform(rng, 0.0, 1.0)};
      bool finite = true;
      const double want = approximation_value(approx, point, finite);
      if (!finite) continue;  // saturate and select treat NaN operands differently
      const double got = p.evaluate(point);
      ASSERT_TRUE(same(got, want)) << text << " at " << point[0] << ", " << point[1] << ", "
                                   << point[2] << ": " << got << " vs " << want;
      ++compared;
    }
  }
  EXPECT_GT(compared, 8000);
}

TEST(ReferenceFormula, OperatorsHaveCsPrecedence) {
  EXPECT_EQ(at(compile("1 + 2 * 3 < 8 && !(2 > 3) || 0"), {}), 1.0);
  EXPECT_EQ(at(compile("x > 0 ? x : -x", {"x"}), {-2.5}), 2.5);
  EXPECT_EQ(at(compile("x < 0 ? -1 : x < 1 ? 0 : 1", {"x"}), {0.5}), 0.0);
  EXPECT_EQ(at(compile("x == 2 != 0", {"x"}), {2.0}), 1.0);
  EXPECT_EQ(at(compile("-x^2", {"x"}), {3.0}), -9.0);   // ^ binds tighter than the sign
  EXPECT_EQ(at(compile("x^2^3", {"x"}), {2.0}), 64.0);  // left-associative, as expr/parse.hpp
  EXPECT_EQ(at(compile("x^0.5", {"x"}), {2.0}), std::sqrt(2.0));
  EXPECT_EQ(at(compile("x^-0.5", {"x"}), {4.0}), 0.5);
  EXPECT_EQ(at(compile("2^x", {"x"}), {10.0}), 1024.0);
  EXPECT_EQ(at(compile("x^(1/3)", {"x"}), {8.0}), 2.0);
  EXPECT_EQ(at(compile("select(x >= 1, 10, 20)", {"x"}), {1.0}), 10.0);
  EXPECT_EQ(at(compile("select(x, 10, 20)", {"x"}), {0.0}), 20.0);  // any condition: != 0
}

TEST(ReferenceFormula, IntegerExponentsStayExactPowers) {
  const Program p = compile("x^40 + pow(x, -3) + x^-1", {"x"});
  int ipow = 0;
  for (const Instruction& in : p.code) ipow += in.op == ProgramOp::IPow ? 1 : 0;
  EXPECT_EQ(ipow, 3);
  EXPECT_EQ(at(p, {-2.0}), std::ldexp(1.0, 40) - 0.125 - 0.5);  // -2 to an integer power
  EXPECT_EQ(at(compile("x^0", {"x"}), {std::nan("")}), 1.0);
  EXPECT_EQ(at(compile("x^1", {"x"}), {-7.0}), -7.0);
  // Beyond the int range: pow.
  EXPECT_EQ(at(compile("x^10000000000", {"x"}), {1.0}), 1.0);
}

TEST(ReferenceFormula, TheCMathLibraryInDouble) {
  struct Case {
    const char* formula;
    double x, want;
  };
  // Read at run time, so that the compiler's own (correctly rounded) folding of std::cbrt and
  // the like does not stand in for the library's.
  static volatile double read_at_run_time = 0.375;
  const double x = read_at_run_time;
  const Case cases[] = {
      {"abs(x)", -x, x},
      {"fabs(x)", -x, x},
      {"sign(x)", -x, -1.0},
      {"sqrt(x)", x, std::sqrt(x)},
      {"cbrt(x)", -x, std::cbrt(-x)},
      {"exp(x)", x, std::exp(x)},
      {"exp2(x)", x, std::exp2(x)},
      {"expm1(x)", x, std::expm1(x)},
      {"log(x)", x, std::log(x)},
      {"log2(x)", x, std::log2(x)},
      {"log10(x)", x, std::log10(x)},
      {"log1p(x)", x, std::log1p(x)},
      {"sin(x)", x, std::sin(x)},
      {"cos(x)", x, std::cos(x)},
      {"tan(x)", x, std::tan(x)},
      {"asin(x)", x, std::asin(x)},
      {"acos(x)", x, std::acos(x)},
      {"atan(x)", x, std::atan(x)},
      {"atan2(x, -1)", x, std::atan2(x, -1.0)},
      {"sinh(x)", x, std::sinh(x)},
      {"cosh(x)", x, std::cosh(x)},
      {"tanh(x)", x, std::tanh(x)},
      {"asinh(x)", x, std::asinh(x)},
      {"acosh(x + 1)", x, std::acosh(x + 1)},
      {"atanh(x)", x, std::atanh(x)},
      {"erf(x)", x, std::erf(x)},
      {"erfc(x)", x, std::erfc(x)},
      {"floor(x * 10)", x, 3.0},
      {"ceil(x * 10)", x, 4.0},
      {"trunc(-x * 10)", x, -3.0},
      {"round(x * 4)", x, 2.0},  // 1.5 rounds away from zero
      {"pow(x, 2.4)", x, std::pow(x, 2.4)},
      {"pow(-x, 3)", x, -x * x * x},
      {"hypot(x, 1e300)", x, 1e300},
      {"fmod(-x, 0.25)", x, std::fmod(-x, 0.25)},
      {"fmin(x, 0.1)", x, 0.1},
      {"fmax(x, 0.1)", x, x},
      {"min(x, 0.1)", x, 0.1},
      {"max(x, 0.1)", x, x},
      {"copysign(x, -1)", x, -x},
      {"clamp(x, 0.4, 1)", x, 0.4},
      {"saturate(x + 1)", x, 1.0},
      {"rsqrt(x)", x, 1 / std::sqrt(x)},
      {"inversesqrt(x)", x, 1 / std::sqrt(x)},
      {"rcp(x)", x, 1 / x},
      {"fma(x, 2, 1)", x, 1.75},
      {"85 * pi / 180 + x", x, 85 * std::numbers::pi / 180 + x},
  };
  for (const Case& c : cases) EXPECT_EQ(at(compile(c.formula, {"x"}), {c.x}), c.want) << c.formula;
}

TEST(ReferenceFormula, BuiltinReferencesByName) {
  const Program p = compile("fresnel_dielectric(c, 1.5) + smith_ggx_g1(c, 0.3)", {"c"});
  const double c = 0.6, g1 = 2 * c / (c + std::sqrt(0.09 + (1 - 0.09) * c * c));
  EXPECT_NEAR(at(p, {c}), fresnel_dielectric(c, 1.5) + g1, 1e-15);
  // The whole text a built-in's name (either spelling): called with its argument names.
  for (const char* name : {"fresnel-conductor", "fresnel_conductor"}) {
    const Program q = compile(name);
    EXPECT_EQ(q.inputs, (std::vector<std::string>{"cos_theta", "ior_n", "ior_k"}));
    EXPECT_EQ(at(q, {0.5, 0.3, 3.0}), fresnel_conductor(0.5, 0.3, 3.0));
  }
  const Program e = compile("exp");  // the rational targets' names too
  EXPECT_EQ(e.inputs, (std::vector<std::string>{"x"}));
  EXPECT_EQ(at(e, {1.0}), std::exp(1.0));
}

TEST(ReferenceFormula, OutputsAreVariablesDefinitionsThenTheReference) {
  const Program p =
      compile("F0 + (1 - F0) * m^5", {}, {"m = 1 - cos(theta)", "F0 = ((n - 1) / (n + 1))^2"});
  EXPECT_EQ(p.inputs, (std::vector<std::string>{"theta", "n"}));  // in order of first use
  EXPECT_EQ(p.output_names,
            (std::vector<std::string>{"theta", "n", "m", "F0", std::string(kReferenceOutput)}));
  std::vector<double> out(5);
  p.evaluate_all(std::vector<double>{0.0, 1.5}, out);
  EXPECT_EQ(out[2], 0.0);
  EXPECT_NEAR(out[3], 0.04, 1e-17);
  EXPECT_EQ(out[4], out[3]);
  EXPECT_EQ(p.evaluate(std::vector<double>{0.0, 1.5}), out[4]);
  EXPECT_EQ(p.description, "F0 + (1 - F0) * m^5");
  // Given variables keep their order, used or not.
  const Program q = compile("y", {"y", "x"});
  EXPECT_EQ(q.output_names, (std::vector<std::string>{"y", "x", "reference"}));
}

TEST(ReferenceFormula, ConstantsFold) {
  const Program p = compile("x * (85 * pi / 180) + cos(0) + 0 * x", {"x"});
  int constants = 0, ops = 0;
  for (const Instruction& in : p.code) {
    constants += in.op == ProgramOp::Const ? 1 : 0;
    ops += in.op == ProgramOp::Const || in.op == ProgramOp::Input ? 0 : 1;
  }
  EXPECT_EQ(constants, 3);  // 85 pi / 180, 1 and 0 (0 * x is not folded: x may be inf)
  EXPECT_EQ(ops, 4);
  EXPECT_EQ(at(p, {2.0}), 2.0 * (85 * std::numbers::pi / 180) + 1.0);
}

void expect_error(const Error& e, const std::string& source, int line, int column,
                  const std::string& message) {
  EXPECT_EQ(e.where().source, source) << e.what();
  EXPECT_EQ(e.where().line, line) << e.what();
  EXPECT_EQ(e.where().column, column) << e.what();
  EXPECT_EQ(e.message(), message) << e.what();
}

TEST(ReferenceFormulaErrors, EachWithItsMessageAndColumn) {
  expect_error(error_of("acoss(x)"), "reference", 1, 1,
               "unknown function 'acoss' (did you mean acos?)");
  const Error far = error_of("2 * zzzzzzzzq(x)");
  EXPECT_EQ(far.where().column, 5);
  EXPECT_NE(far.message().find("unknown function 'zzzzzzzzq' (known: abs, acos, acosh,"),
            std::string::npos)
      << far.message();
  EXPECT_NE(far.message().find("fresnel_schlick"), std::string::npos);
  expect_error(error_of("x + y", {"x"}), "reference", 1, 5, "unknown variable 'y' (known: x, pi)");
  expect_error(error_of("atan2(x)", {"x"}), "reference", 1, 1, "atan2 takes 2 arguments, got 1");
  expect_error(error_of("sqrt(x, x)", {"x"}), "reference", 1, 1, "sqrt takes 1 argument, got 2");
  expect_error(error_of("fresnel_schlick(x)", {"x"}), "reference", 1, 1,
               "fresnel_schlick takes 2 arguments, got 1");
  expect_error(error_of("x + * 2", {"x"}), "reference", 1, 5,
               "unexpected '*': an operand is missing");
  expect_error(error_of("(x + 1", {"x"}), "reference", 1, 7,
               "expected ')' to close the '(' at column 1, found end of formula");
  expect_error(error_of("x ? 1", {"x"}), "reference", 1, 6,
               "expected ':' after the first branch of '?' at column 3, found end of formula");
  expect_error(error_of("x = 1", {"x"}), "reference", 1, 3,
               "unexpected '=' (a definition is 'name = formula'; '==' compares)");
  expect_error(error_of("2x"), "reference", 1, 2, "unexpected 'x' after the number 2");
  expect_error(error_of("x % 2", {"x"}), "reference", 1, 3, "unexpected character '%'");
  expect_error(error_of("sin + 1"), "reference", 1, 1,
               "function 'sin' needs arguments in parentheses");
  expect_error(error_of("   "), "reference", 1, 4, "empty formula");
  expect_error(error_of("reference * 2"), "reference", 1, 1,
               "'reference' names the reference's own output: give the variable another name");
}

TEST(ReferenceFormulaErrors, DefinitionsAreLocatedByPosition) {
  expect_error(error_of("k * x", {"x"}, {"k = 2", "k = 3"}), "definitions", 2, 1,
               "definition 'k' redefines definition 1");
  expect_error(error_of("k", {"x"}, {"x = 2"}), "definitions", 1, 1,
               "definition 'x' redefines the variable x");
  expect_error(error_of("k", {}, {"k = k + 1"}), "definitions", 1, 1,
               "definition 'k' redefines the variable k");
  expect_error(error_of("k", {}, {"pi = 3"}), "definitions", 1, 1,
               "definition 'pi' redefines the constant pi");
  expect_error(error_of("k", {}, {"erf = 3"}), "definitions", 1, 1,
               "definition 'erf' redefines the function erf");
  expect_error(error_of("k", {"x"}, {"k = x +"}), "definitions", 1, 8,
               "unexpected end of formula: an operand is missing");
  expect_error(error_of("k", {"x"}, {"2 = x"}), "definitions", 1, 1,
               "expected 'name = formula', got '2 = x'");
  // A definition may use only the names before it.
  expect_error(error_of("a", {"x"}, {"a = b", "b = x"}), "definitions", 1, 5,
               "unknown variable 'b' (known: x, pi)");
}

TEST(ReferenceFormulaErrors, SizeLimitsLikeTheApproximationParser) {
  auto nested = [](int levels) {
    return std::string(static_cast<std::size_t>(levels) - 1, '(') + "-2" +
           std::string(static_cast<std::size_t>(levels) - 1, ')');
  };
  ParseOptions o;
  EXPECT_NO_THROW(parse_formula(nested(kMaxFormulaNesting), o));
  EXPECT_NO_THROW(compile(nested(kMaxFormulaNesting)));
  const Error e = error_of(nested(kMaxFormulaNesting + 1));
  EXPECT_NE(e.message().find("nested more than 256 levels"), std::string::npos) << e.what();
  EXPECT_EQ(e.where().column, kMaxFormulaNesting + 1);
  EXPECT_THROW(compile(std::string(300, '-') + "x"), Error);
  std::string ternary = "x";
  for (int i = 0; i < 100000; ++i) ternary += " ? x : x";
  EXPECT_THROW(compile(ternary, {"x"}), Error);
  // A long sum is flat here (the program is straight-line code): no depth limit applies.
  std::string sum = "x";
  for (int i = 0; i < 20000; ++i) sum += "+x";
  EXPECT_EQ(at(compile(sum, {"x"}), {1.0}), 20001.0);
}

TEST(ReferenceFormulaErrors, FormulaAndShaderTogether) {
  ReferenceText t;
  t.formula = "x";
  t.shader_source = "float f(float x) { return x; }";
  t.function = "f";
  EXPECT_THROW(compile_reference(t), Error);
  ReferenceText v;
  v.formula = "x";
  v.variables = {"x", "x"};
  EXPECT_THROW(compile_reference(v), Error);
  v.variables = {"x y"};
  EXPECT_THROW(compile_reference(v), Error);
}

TEST(ReferenceConstant, Evaluates) {
  EXPECT_EQ(evaluate_constant("pi/2", "domain"), std::numbers::pi / 2);
  EXPECT_EQ(evaluate_constant(" 85*pi/180 ", "domain"), 85 * std::numbers::pi / 180);
  EXPECT_EQ(evaluate_constant("1e-3", "domain"), 1e-3);
  EXPECT_EQ(evaluate_constant("-acos(-1)", "domain"), -std::numbers::pi);
  try {
    (void)evaluate_constant("2 * x", "domain");
    FAIL();
  } catch (const Error& e) {
    expect_error(e, "domain", 1, 5,
                 "a constant cannot name a variable ('x'); pi is the one named constant");
  }
  try {
    (void)evaluate_constant("1/0", "bound");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.message(), "'1/0' is not a finite number (inf)");
    EXPECT_EQ(e.where().source, "bound");
  }
  EXPECT_THROW((void)evaluate_constant("sqrt(-1)", "bound"), Error);
  EXPECT_THROW((void)evaluate_constant("", "bound"), Error);
}

TEST(ReferenceFunctionNames, SortedWithTheBuiltins) {
  const std::vector<std::string> names = reference_function_names();
  EXPECT_TRUE(std::is_sorted(names.begin(), names.end()));
  EXPECT_TRUE(std::adjacent_find(names.begin(), names.end()) == names.end());
  for (const char* n : {"acos", "erf", "atan2", "clamp", "select", "fma", "fresnel_exact", "ggx_d"})
    EXPECT_TRUE(std::binary_search(names.begin(), names.end(), n)) << n;
  for (const char* n : {"mix", "lerp", "smoothstep"})  // shader built-ins only
    EXPECT_FALSE(std::binary_search(names.begin(), names.end(), n)) << n;
}

}  // namespace
}  // namespace shaderfit::reference
