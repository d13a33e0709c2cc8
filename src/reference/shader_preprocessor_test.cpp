// The preprocessor of the shader front end (language_shader_preprocessor.hpp): function-like
// macros, conditional groups, #undef, a byte-order mark and CRLF lines, and each refused or
// malformed line an error at its line and column.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "shaderfit/core/error.hpp"
#include "shaderfit/expr/print.hpp"
#include "reference/shader_test_util.hpp"
#include "shaderfit/reference/language.hpp"
#include "shaderfit/reference/program_formula.hpp"

namespace shaderfit::reference {
namespace {

using testing::at;
using testing::formula_of;
using testing::kSubsetNote;
using testing::located;
using testing::shader;
using testing::shader_error;


TEST(ShaderPreprocessor, FunctionLikeMacrosExpandWithTheirArguments) {
  const Program p = shader(R"(
#define SQR(x) ((x)*(x))
#define MAD(a,b,c) (a*b+c)
#define POW4(x) SQR(SQR(x))
#define LERP(a, b, t) MAD(t, ((b) - (a)), a)
#define PI 3.14159265
#define TWO_PI_SQ SQR(2.0 * PI)
#define ONE() 1.0
float f(float x, float y) {
  float a = POW4(x + 1.0);             // ((x + 1)^2)^2
  float b = MAD(x + 1.0, 2.0, 1.0);    // x + 1.0*2.0 + 1.0: the text, not a value
  float c = MAD(max(x, y), min(x, ONE()), 2.0);
  return a + b * 10.0 + c * 100.0 + LERP(x, y, 0.25) * 1000.0 + TWO_PI_SQ;
}
)");
  for (const double x : {-1.5, 0.25, 2.0}) {
    for (const double y : {-0.5, 3.0}) {
      const double want = std::pow(x + 1, 4) + (x + 3) * 10 +
                          (std::max(x, y) * std::min(x, 1.0) + 2) * 100 +
                          (0.25 * (y - x) + x) * 1000 + std::pow(2 * 3.14159265, 2);
      EXPECT_NEAR(at(p, {x, y}), want, 1e-9 * std::fabs(want)) << x << ", " << y;
    }
  }
}

TEST(ShaderPreprocessor, AMacroReplacesABuiltinAndIsNotExpandedInsideItself) {
  // GLSL has no saturate; a macro gives it one. Here it clamps to 0.5 to tell it from the
  // built-in, and cos inside cos's expansion is the built-in.
  const Program p = shader(R"(
#define saturate(x) clamp(x, 0.0, 0.5)
#define cos(x) (cos(x) * 2.0)
#define LOOP LOOP + 1.0
float f(float x) { return saturate(x) + cos(x); }
)");
  for (const double x : {-1.0, 0.25, 0.75, 2.0})
    EXPECT_NEAR(at(p, {x}), std::clamp(x, 0.0, 0.5) + 2 * std::cos(x), 1e-15) << x;
}

TEST(ShaderPreprocessor, TheLoweredFormulaIsTheExpansion) {
  const Program p = shader(R"(
#define saturate(x) clamp(x, 0.0, 1.0)
#define SQR(x) ((x)*(x))
float f(float x) { return SQR(saturate(x)) * 2.0; }
)");
  const ProgramFormula formula = program_formula(p, std::vector<std::string>{"x"});
  ASSERT_TRUE(formula.formula) << formula.why;
  EXPECT_EQ(to_infix(*formula.formula), "saturate(x) * saturate(x) * 2");
}

TEST(ShaderPreprocessor, MacrosNeverUsedAreNeverRead) {
  // Bodies outside the subset (# and ##, vectors, strings) are errors only where expanded.
  const std::string unused = R"(#define STR(x) #x
#define CAT(a, b) a ## b
#define V(x) vec3(x, x, x)
#define MESSAGE "hello"
#define VARIADIC(...) __VA_ARGS__
#define EMPTY
float f(float x) { return x + 1.0; }
)";
  EXPECT_EQ(at(shader(unused), {2.0}), 3.0);
  EXPECT_EQ(located(shader_error(unused + "float g(float x) { return STR(x); }", "g")),
            "1:16: unexpected character '#'");
  EXPECT_EQ(located(shader_error(unused + "float g(float x) { return x + MESSAGE; }", "g")),
            "4:17: unexpected character '\"'");
  EXPECT_EQ(located(shader_error(unused + "float g(float x) { return VARIADIC(x); }", "g")),
            "5:18: variadic macros are not supported (VARIADIC(...))" + kSubsetNote);
  // A macro without a value is nothing, as in C: here an operand goes missing.
  EXPECT_EQ(located(shader_error(unused + "float g(float x) { return x + EMPTY; }", "g")),
            "8:36: unexpected ';': an operand is missing");
}

TEST(ShaderPreprocessor, ObjectLikeMacrosAreTextWhereUsed) {
  // As in C: a macro is its tokens where it is used, with the definition in force there; #undef
  // and a new #define change the uses after them.
  const Program p = shader(R"(
#define K 1.0
#undef K
#define K 2.0
const float kThree = K + 1.0;
float g(float x) { return x * K + kThree; }
#undef K
#define K 5.0
float f(float x) {
#define TEN 10.0
  return g(x) * TEN + K;
}
#undef TEN
)");
  EXPECT_EQ(at(p, {1.5}), (1.5 * 2 + 3) * 10 + 5);
  // Types, expressions of locals, and nothing at all (engines' `real`, `X2`, `INLINE`); a
  // typedef of a type names it too.
  const Program q = shader(R"(
#define real float
#define real3 float3
#define INLINE
#define X2 (x * x)
typedef half precise_t;
INLINE real sq(real x) { return X2; }
real f(real x) {
  real3 v = real3(x, 1.0, 2.0);
  precise_t y = sq(v.x) + v.z;
  return y;
}
)",
                           "f", {}, "test.hlsl");
  EXPECT_EQ(at(q, {3.0}), 11.0);
}

TEST(ShaderPreprocessor, ConditionalGroupsChooseTheCode) {
  const Program p = shader(R"(
#define USE_FAST 1
#define QUALITY 2
#ifdef USE_FAST
float base(float x) { return x * (2.0 - x); }
#else
float base(float x) { return sin(x * 1.5707963); }
#endif
#ifndef USE_FAST
this is not valid code at all @ $ " '
#include "missing.glsl"
#bogus directive
#if 1
#else
#endif
#elif QUALITY > 1
float scale(float x) { return 3.0 * x; }
#else
float scale(float x) { return 4.0 * x; }
#endif
#undef USE_FAST
const float kK =
#if defined(USE_FAST) || QUALITY * 2 != 4
  1.0
#elif (QUALITY + 1) * 2 == 6 && !defined USE_FAST
  5.0
#else
  7.0
#endif
;
float f(float x) {
#if QUALITY >= 2
  float y = scale(base(x));
#  if 0
  y = 0.0;
#  endif
#else
  float y = 0.0;
#endif
  return y + kK;
}
)");
  for (const double x : {0.0, 0.5, 1.0}) EXPECT_EQ(at(p, {x}), 3 * x * (2 - x) + 5) << x;
}

TEST(ShaderPreprocessor, IfExpressionsAreCIntegerArithmetic) {
  // Each expression with A = 2, B defined empty, SQR function-like, C not defined.
  const std::vector<std::pair<std::string, bool>> cases = {
      {"1", true},
      {"0", false},
      {"A", true},
      {"A == 2", true},
      {"A > 3", false},
      {"A >= 2 && A <= 2", true},
      {"defined(A) && defined B && !defined(C)", true},
      {"defined C || A - 2", false},
      {"(A + 1) * 2 == 6", true},
      {"7 / A == 3 && 7 % A == 1 && -7 / A == -3", true},
      {"C", false},  // a name that is no macro is 0, as in C
      {"C == 0 && !C", true},
      {"SQR(A) == 4 && SQR(A + 1) == 9", true},
      {"0 && 1 / 0", false},  // && does not evaluate what it does not need
      {"1 || 1 % 0", true},
      {"0x10 == 16 && 010 == 8 && 2u == 2", true},
      {"- -A == +A && !!A", true},
      {"1 + 2 * 3 == 7 && 1 < 2 == 1 && 3 - 1 - 1 == 1", true},
  };
  for (const auto& [expression, holds] : cases) {
    const std::string source = "#define A 2\n#define B\n#define SQR(x) ((x) * (x))\n#if " +
                               expression +
                               "\nfloat f(float x) { return 1.0; }\n#else\nfloat f(float x) { "
                               "return 0.0; }\n#endif\n";
    EXPECT_EQ(at(shader(source), {0.0}), holds ? 1.0 : 0.0) << expression;
  }
}

TEST(ShaderPreprocessor, ByteOrderMarkAndWindowsLineEnds) {
  const std::string bom = "\xEF\xBB\xBF";
  const Program p =
      shader(bom +
             "// Windows file \xC2\xB0 with BOM and CRLF\r\n"
             "#define SQR(x) \\\r\n  ((x) * (x))\r\n"
             "float f(float x)\r\n{\r\n    return SQR(x); // \xE2\x80\x94 dash\r\n}\r\n");
  EXPECT_EQ(at(p, {3.0}), 9.0);
  // Columns count from after the mark.
  EXPECT_EQ(located(shader_error(bom + "float f(float x) { return x @ 2.0; }")),
            "1:29: unexpected character '@'");
  // A continued #define: its tokens keep their lines.
  EXPECT_EQ(
      located(shader_error("#define BAD(x) \\\n  (x + $)\nfloat f(float x) { return BAD(x); }")),
      "2:8: unexpected character '$'");
}

TEST(ShaderPreprocessor, ErrorsAreLocated) {
  const std::string f = "float f(float x) { return x; }\n";
  EXPECT_EQ(located(shader_error(f + "#endif")), "2:1: #endif without #if");
  EXPECT_EQ(located(shader_error(f + "#else\n")), "2:1: #else without #if");
  EXPECT_EQ(located(shader_error("#ifdef A\n#if 1\n#endif\n" + f)),
            "1:1: #ifdef is not closed: its #endif is missing");
  EXPECT_EQ(located(shader_error("#if 1\n" + f)), "1:1: #if is not closed: its #endif is missing");
  EXPECT_EQ(located(shader_error("#if 0\n#else\n#else\n#endif\n" + f)), "3:1: #else after #else");
  EXPECT_EQ(located(shader_error("#if 1\n#else\n#elif 1\n#endif\n" + f)), "3:1: #elif after #else");
  EXPECT_EQ(located(shader_error("#include \"common.glsl\"\n" + f)),
            "1:1: #include is not supported (\"common.glsl\"): the reference is read from its one "
            "file" +
                kSubsetNote);
  EXPECT_EQ(std::string(shader_error("\n  #include <lib.hlsl>\n" + f).what()),
            "test.glsl:2:3: #include is not supported (<lib.hlsl>): the reference is read from "
            "its one file" +
                kSubsetNote);
  EXPECT_EQ(located(shader_error("#line 10\n" + f)),
            "1:1: preprocessor directive #line is not supported (only #define, #undef, #if, "
            "#ifdef, #ifndef, #elif, #else, #endif, #error, #version, #extension and #pragma)" +
                kSubsetNote);
  EXPECT_EQ(located(shader_error("#if 1\n#error needs   a newer engine\n#endif\n" + f)),
            "2:1: #error needs a newer engine");

  const std::string sqr = "#define SQR(x) ((x)*(x))\n";
  EXPECT_EQ(located(shader_error(sqr + "float f(float x) { return SQR(x, 2.0); }")),
            "2:27: macro 'SQR' takes 1 argument, got 2");
  EXPECT_EQ(located(shader_error("#define ONE() 1.0\nfloat f(float x) { return ONE(x); }")),
            "2:27: macro 'ONE' takes 0 arguments, got 1");
  EXPECT_EQ(located(shader_error("#define MAD(a, b, c) (a * b + c)\n"
                                 "float f(float x) { return MAD(x, 2.0); }")),
            "2:27: macro 'MAD' takes 3 arguments, got 2");
  EXPECT_EQ(located(shader_error(sqr + "float f(float x) { return SQR(x; }")),
            "2:30: the arguments of macro 'SQR' are not closed: ')' is missing");
  EXPECT_EQ(located(shader_error("#define F(x, x) x\n#define G(x y) x\nfloat f(float x) { "
                                 "return G(x, x); }")),
            "2:13: expected ',' or ')' after a macro parameter, found 'y'");
  EXPECT_EQ(located(shader_error("#define 1 2\n" + f)), "1:9: #define needs a macro name");

  EXPECT_EQ(located(shader_error("#if 1 ^ 2\n#endif\n" + f)),
            "1:7: operator '^' is not supported in #if (its operators: ! * / % + - < > <= >= "
            "== != && || and parentheses)");
  EXPECT_EQ(located(shader_error("#if 0\n#elif (1 << 2)\n#endif\n" + f)),
            "2:10: operator '<<' is not supported in #elif (its operators: ! * / % + - < > <= "
            ">= == != && || and parentheses)");
  EXPECT_EQ(located(shader_error("#define PI 3.14159\n#if PI > 3\n#endif\n" + f)),
            "1:12: #if takes integers, not '3.14159'");
  EXPECT_EQ(located(shader_error("#if 1 / (2 - 2)\n#endif\n" + f)), "1:7: division by zero in #if");
  EXPECT_EQ(located(shader_error("#if 1 +\n#endif\n" + f)),
            "1:8: expected a value in #if, found the end of the line");
  EXPECT_EQ(located(shader_error("#if (1\n#endif\n" + f)),
            "1:7: expected ')' in #if, found the end of the line");
  EXPECT_EQ(located(shader_error("#ifdef 3\n#endif\n" + f)),
            "1:8: #ifdef needs a macro name, found '3'");
}

TEST(ShaderPreprocessor, HostileMacrosStayWithinLimits) {
  // An expansion that doubles at every level, calls nested past the limit, deep #if parentheses.
  std::string doubling = "#define D(x) x x\nfloat f(float x) { return ";
  for (int i = 0; i < 30; ++i) doubling += "D(";
  doubling += "x" + std::string(30, ')') + "; }";
  EXPECT_NE(shader_error(doubling).message().find("macro expansions make more than"),
            std::string::npos);
  std::string deep = "#define I(x) x\nfloat f(float x) { return ";
  for (int i = 0; i < 300; ++i) deep += "I(";
  deep += "x" + std::string(300, ')') + "; }";
  EXPECT_NE(shader_error(deep).message().find("macros nested more than 256 levels"),
            std::string::npos);
  const std::string parens =
      "#if " + std::string(300, '(') + "1" + std::string(300, ')') + "\n#endif\n";
  EXPECT_NE(shader_error(parens + "float f(float x) { return x; }").message().find("nested"),
            std::string::npos);
  // Macros that call each other stop where each would expand inside itself.
  const Program p = shader(
      "float A(float x) { return x; }\n#define A(x) B(x) + 1.0\n#define B(x) A(x) * 2.0\n"
      "float f(float x) { return A(x); }");
  EXPECT_EQ(at(p, {3.0}), 3 * 2.0 + 1);
}

}  // namespace
}  // namespace shaderfit::reference
