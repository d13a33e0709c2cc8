// The shader front end's statements (language_shader.cpp): out and inout parameters of the
// helpers a reference calls, for loops with a constant trip count (unrolled; break and
// continue), variables read before they hold a value, and HLSL's attributes before statements.
// Each is checked by the program's values at points, against the C++ it means, and each bad
// input by its message and location.
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


// --- out and inout parameters ----------------------------------------------------------------

TEST(ShaderOutParameters, VoidHelperWritesTheCallersVariable) {
  // /work/fuzz/shaders/g09_spot.glsl: Karis' windowed falloff written through an out parameter.
  const char* source = R"(
float sqr(float x) { return x*x; }
void windowedFalloff(float dist, float radius, out float att) {
    float d_r = dist / radius;
    float win = clamp(1.0 - sqr(sqr(d_r)), 0.0, 1.0);
    att = sqr(win) / (dist * dist + 1.0);
}
float spotLight(float dist, float radius, float cosAngle, float cosOuter, float cosInner) {
    float att;
    windowedFalloff(dist, radius, att);
    float spot = smoothstep(cosOuter, cosInner, cosAngle);
    return att * spot;
}
)";
  const Program p = shader(source, "spotLight");
  auto want = [](double dist, double radius, double c, double lo, double hi) {
    const double d = dist / radius;
    const double win = std::clamp(1.0 - d * d * (d * d), 0.0, 1.0);
    const double att = win * win / (dist * dist + 1.0);
    const double t = std::clamp((c - lo) / (hi - lo), 0.0, 1.0);
    return att * (t * t * (3.0 - 2.0 * t));
  };
  for (const double dist : {0.5, 2.0, 7.5})
    for (const double c : {0.7, 0.85, 0.99})
      EXPECT_NEAR(at(p, {dist, 8.0, c, 0.8, 0.95}), want(dist, 8.0, c, 0.8, 0.95), 1e-15)
          << dist << ", " << c;
  EXPECT_EQ(formula_of(p).find("none"), std::string::npos) << formula_of(p);
}

TEST(ShaderOutParameters, InoutInHlslSpellingsAndFloatHelpers) {
  // /work/fuzz/shaders/h10_occlusion_fog.hlsl: the reference's own parameter passed inout.
  const char* fog = R"(
void ApplyExpFog(inout float radiance, float dist, float density, float fogColor)
{
    float f = exp(-density * dist);
    radiance = lerp(fogColor, radiance, f);
}
float FoggedRadiance(float radiance, float dist, float density, float fogColor)
{
    ApplyExpFog(radiance, dist, density, fogColor);
    return radiance;
}
)";
  const Program p = shader(fog, "FoggedRadiance", {}, "fog.hlsl");
  for (const double r : {0.0, 0.3, 4.0}) {
    const double f = std::exp(-0.2 * 3.0);
    EXPECT_NEAR(at(p, {r, 3.0, 0.2, 0.5}), 0.5 + f * (r - 0.5), 1e-15) << r;
  }
  // HLSL's `in out`, a float helper that also writes two outs, and an int caller variable (the
  // written value is converted to its type).
  const Program q = shader(R"(
float split(float x, in out float acc, out float frac_part, out int whole) {
  frac_part = x - floor(x);
  whole = int(floor(x));
  acc += x;
  return 2.0 * x;
}
float f(float x) {
  float acc = 1.0, fr;
  int w = 0;
  float twice = split(x, acc, fr, w) + 1.0;
  return twice * 1000.0 + acc * 100.0 + fr * 10.0 + float(w);
})");
  for (const double x : {0.25, 2.75}) {
    const double want =
        (2 * x + 1) * 1000 + (1 + x) * 100 + (x - std::floor(x)) * 10 + std::floor(x);
    EXPECT_EQ(at(q, {x}), want) << x;
  }
}

TEST(ShaderOutParameters, TheValueAtTheReturnIsWrittenBack) {
  // An early return keeps the out parameter's value at that return; the code after it does not
  // change it on the paths that returned.
  const Program p = shader(R"(
void g(float x, out float y) {
  y = 1.0;
  if (x > 0.5) return;
  y = 2.0;
  if (x > 0.25) { y = 3.0; return; }
  y += x;
}
float f(float x) {
  float a = -1.0;
  g(x, a);
  return a;
})");
  EXPECT_EQ(at(p, {0.75}), 1.0);
  EXPECT_EQ(at(p, {0.375}), 3.0);
  EXPECT_EQ(at(p, {0.125}), 2.125);
  // Written in both branches; called inside a branch of the caller (only that branch's paths
  // get the value); the same variable passed twice takes the last parameter's value.
  const Program q = shader(R"(
void sides(float x, out float lo, out float hi) {
  if (x < 0.0) { lo = x; hi = -x; } else { lo = -x; hi = x; }
}
float f(float x) {
  float a = 5.0, b = 7.0;
  if (x > -0.5) sides(x, a, b);
  sides(x * 2.0, b, b);
  return a * 100.0 + b;
})");
  EXPECT_EQ(at(q, {0.25}), -25.0 + 0.5);
  EXPECT_EQ(at(q, {-0.25}), -25.0 + 0.5);
  EXPECT_EQ(at(q, {-1.0}), 500.0 + 2.0);
}

TEST(ShaderOutParameters, Errors) {
  const char* helper = "void g(float x, out float y) { y = x; }\n";
  EXPECT_EQ(located(shader_error(std::string(helper) +
                                 "float f(float x) { float y; g(x, y * 2.0); return y; }")),
            "2:34: the out parameter 'y' of g writes its argument: it must be a variable (a local "
            "or a parameter, or a member, element or component of one), found 'y'");
  EXPECT_EQ(located(shader_error(std::string(helper) +
                                 "float f(float x) { float y; g(x, (y)); return y; }")),
            "2:34: the out parameter 'y' of g writes its argument: it must be a variable (a local "
            "or a parameter, or a member, element or component of one), found '('");
  EXPECT_EQ(located(shader_error(std::string(helper) +
                                 "float f(float x) { const float k = 1.0; g(x, k); return k; }")),
            "2:46: cannot pass the constant 'k' to the out parameter 'y' of g");
  EXPECT_EQ(located(shader_error(std::string(helper) + "const float K = 1.0;\n" +
                                 "float f(float x) { g(x, K); return x; }")),
            "3:25: cannot pass the file-scope constant 'K' to the out parameter 'y' of g");
  EXPECT_EQ(located(shader_error(std::string(helper) + "uniform float u;\n" +
                                 "float f(float x) { g(x, u); return x; }")),
            "3:25: uniforms are not supported (u)" + kSubsetNote);
  EXPECT_EQ(located(shader_error(std::string(helper) +
                                 "float f(float x) { float yy; g(x, y); return yy; }")),
            "2:35: unknown identifier 'y'");
  EXPECT_EQ(located(shader_error(std::string(helper) +
                                 "float f(float x) { float y; g(x, true); return y; }")),
            "2:34: the out parameter 'y' of g writes its argument: it must be a variable (a local "
            "or a parameter, or a member, element or component of one), found 'true'");
  // An out parameter holds no value until written; an inout argument is read.
  EXPECT_EQ(located(shader_error("void g(float x, out float y) { y += x; }\n"
                                 "float f(float x) { float y = 1.0; g(x, y); return y; }")),
            "1:32: the out parameter 'y' is read before it is given a value");
  EXPECT_EQ(located(shader_error("void g(inout float y) { y *= 2.0; }\n"
                                 "float f(float x) {\n  float y;\n  g(y);\n  return y;\n}")),
            "4:5: 'y' is read before it is given a value (declared at line 3)");
  // A void function's call is a statement; void functions return no value.
  EXPECT_EQ(located(shader_error(std::string(helper) +
                                 "float f(float x) { float y; return g(x, y) + y; }")),
            "2:36: function 'g' returns void: its call is a statement of its own, not a value");
  EXPECT_EQ(located(shader_error("void g(float x) { return x; }\n"
                                 "float f(float x) { g(x); return x; }")),
            "1:26: function 'g' returns void: return takes no value");
  EXPECT_EQ(located(shader_error("void g(out float y) { }\n"
                                 "float f(float x) {\n  float y;\n  g(y);\n  return y;\n}")),
            "5:10: 'y' is read before it is given a value (declared at line 3)");
  // The reference itself returns one float: its parameters are inputs only.
  const std::string wrap = " from a function that returns the value)";
  EXPECT_EQ(located(shader_error("float f(float x, out float y) { y = x; return x; }")),
            "1:18: parameter 'y' of f is out: the reference's parameters are its inputs and its "
            "one result is the float it returns (call f" +
                wrap);
  EXPECT_EQ(located(shader_error("float f(inout float x) { return x; }")),
            "1:9: parameter 'x' of f is inout: the reference's parameters are its inputs and its "
            "one result is the float it returns (call f" +
                wrap);
  EXPECT_EQ(located(shader_error("float f(in out float x) { return x; }")),
            "1:9: parameter 'x' of f is inout: the reference's parameters are its inputs and its "
            "one result is the float it returns (call f" +
                wrap);
  EXPECT_EQ(located(shader_error("void f(float x) { }")),
            "1:1: function 'f' returns void: a reference returns a float");
}

// --- for loops -------------------------------------------------------------------------------

TEST(ShaderForLoops, UnrolledWithAConstantTripCount) {
  // /work/fuzz/shaders/g10_acos.glsl: (1 - c)^5 the long way.
  const Program p = shader(R"(
float schlickWeightLoop(float c) {
    float r = 1.0;
    for (int i = 0; i < 5; i++) {
        r *= (1.0 - c);
    }
    return r;
})",
                           "schlickWeightLoop");
  for (const double c : {0.0, 0.25, 0.9}) {
    double want = 1.0;
    for (int i = 0; i < 5; ++i) want *= 1.0 - c;
    EXPECT_EQ(at(p, {c}), want) << c;
  }
  EXPECT_EQ(formula_of(p), "(1 - c) * (1 - c) * (1 - c) * (1 - c) * (1 - c)");

  // The spellings of the header, and the loop's variable as a number in the body.
  struct Case {
    const char* header;
    double want;  // sum of the values the variable takes, at x = 1
  };
  const Case cases[] = {
      {"int i = 0; i < 4; i++", 0 + 1 + 2 + 3},
      {"int i = 0; i < 4; ++i", 6},
      {"int i = 0; i <= 4; i += 1", 10},
      {"int i = 4; i > 0; i--", 4 + 3 + 2 + 1},
      {"int i = 3; i >= 0; --i", 6},
      {"int i = 1; i < 20; i *= 3", 1 + 3 + 9},
      {"int i = 0; i < N; i = i + 2", 0 + 2 + 4},
      {"int i = 0; i < M; i++", 0 + 1 + 2},
      {"float i = 0.5; i < 2.0; i += 0.5", 0.5 + 1.0 + 1.5},
      {"int i = 0, j = 10; i < 3; i++, j--", 0 + 1 + 2},
      {"int i = 5; i < 5; i++", 0},
      {"k = 1; k < 3; k++", 0},  // the loop's variable declared before it: its body reads i = 0
  };
  for (const Case& c : cases) {
    const std::string source =
        "#define N 6\nfloat f(float x) {\n  const int M = 3;\n"
        "  int k = 0, i = 0;\n  float s = 0.0;\n  for (" +
        std::string(c.header) + ") s += float(i) * x;\n  return s;\n}\n";
    EXPECT_EQ(at(shader(source), {1.0}), c.want) << c.header;
  }
  // The variable the loop assigns keeps its last value after it.
  EXPECT_EQ(at(shader("float f(float x) { int k; for (k = 0; k < 3; k++) x *= 2.0; "
                      "return x + float(k); }"),
               {1.0}),
            8.0 + 3.0);
}

TEST(ShaderForLoops, NestedLoopsReturnsBranchesAndCallsInside) {
  const Program p = shader(R"(
float term(float x, int k) { return pow(x, float(k)) / float(k + 1); }
float f(float x) {
  float s = 0.0;
  [unroll] for (int i = 0; i < 3; i++) {
    [unroll(4)] for (int j = 0; j <= i; j++) {
      if (x > float(i + j)) s += term(x, i * j);
      else s -= 1.0;
    }
  }
  for (int n = 1; n < 10; n++) {
    if (s > float(n * 10)) return s * 1000.0;
  }
  return s;
})");
  auto want = [](double x) {
    double s = 0.0;
    for (int i = 0; i < 3; i++)
      for (int j = 0; j <= i; j++) s += x > i + j ? std::pow(x, i * j) / (i * j + 1) : -1.0;
    for (int n = 1; n < 10; n++)
      if (s > n * 10) return s * 1000.0;
    return s;
  };
  for (const double x : {-1.0, 0.5, 1.5, 2.5, 3.5, 5.0})
    EXPECT_NEAR(at(p, {x}), want(x), 1e-12 * std::fabs(want(x))) << x;
}

TEST(ShaderForLoops, BreakAndContinue) {
  const Program p = shader(R"(
float f(float x) {
  float s = 0.0;
  int last = -1;
  for (int i = 0; i < 8; i++) {
    if (float(i) > x * 4.0) break;
    last = i;
    if (i == 2) continue;
    for (int j = 0; j < 4; j++) {
      if (j > i) break;
      if (j == 1) continue;
      s += 1.0;
    }
    s += 10.0;
  }
  return s + float(last) * 1000.0;
})");
  auto want = [](double x) {
    double s = 0.0;
    int last = -1;
    for (int i = 0; i < 8; i++) {
      if (i > x * 4.0) break;
      last = i;
      if (i == 2) continue;
      for (int j = 0; j < 4; j++) {
        if (j > i) break;
        if (j == 1) continue;
        s += 1.0;
      }
      s += 10.0;
    }
    return s + last * 1000.0;
  };
  for (const double x : {-0.5, 0.0, 0.3, 0.6, 0.8, 1.0, 3.0}) EXPECT_EQ(at(p, {x}), want(x)) << x;
  // An unconditional break ends the unrolling; code after it in the body never runs.
  EXPECT_EQ(at(shader("float f(float x) { for (int i = 0; i < 100; i++) { x += 1.0; break; "
                      "x = 0.0; } return x; }"),
               {1.0}),
            2.0);
}

TEST(ShaderForLoops, ReturnsAfterContinueAndOutParametersReturnedInsideALoop) {
  const Program p = shader(R"(
float f(float x) {
  for (int i = 0; i < 6; i++) {
    if (x > float(i)) continue;
    if (x < float(i) - 2.5) break;
    return float(i) * 10.0 + x;
  }
  return -1.0;
})");
  auto want = [](double x) {
    for (int i = 0; i < 6; i++) {
      if (x > i) continue;
      if (x < i - 2.5) break;
      return i * 10.0 + x;
    }
    return -1.0;
  };
  for (const double x : {-5.0, -1.0, 0.0, 2.25, 4.5, 5.0, 7.0}) EXPECT_EQ(at(p, {x}), want(x)) << x;
  const Program q = shader(R"(
void g(float x, out float y) {
  y = 0.0;
  for (int i = 0; i < 4; i++) {
    y += 1.0;
    if (x < float(i)) return;
  }
  y = 100.0;
}
float f(float x) { float y; g(x, y); return y; })");
  EXPECT_EQ(at(q, {-1.0}), 1.0);
  EXPECT_EQ(at(q, {1.5}), 3.0);
  EXPECT_EQ(at(q, {10.0}), 100.0);
}

TEST(ShaderForLoops, Errors) {
  const auto body = testing::function_with;
  const std::string unrolled = ": loops are unrolled, so their trip count must be a constant";
  EXPECT_EQ(located(shader_error(body("for (int i = 0; float(i) < x; i++) y *= 2.0;"))),
            "3:19: the condition of this for loop is not a constant" + unrolled);
  // The loop's variable made to depend on an input stops being a constant.
  EXPECT_EQ(located(shader_error(body("for (int i = 0; i < 4; i++) { if (y > 1.0) i++; }"))),
            "3:19: the condition of this for loop is not a constant" + unrolled);
  EXPECT_EQ(located(shader_error(body("int k;\n  for (k = 0; k < 4; k++) if (y > 1.0) break;"))),
            "4:15: the condition of this for loop is not a constant" + unrolled +
                " (a loop that breaks on some paths must declare its variable in its header: for "
                "(int i = ...))");
  EXPECT_EQ(located(shader_error(body("for (int i = 0; ; i++) y *= 2.0;"))),
            "3:19: a for loop needs a condition" + unrolled);
  EXPECT_EQ(located(shader_error(body("for (int i = 0; i < 65; i++) y *= 2.0;"))),
            "3:3: this for loop runs more than 64 iterations, the most that is unrolled");
  EXPECT_EQ(located(shader_error(body("for (int i = 0; i >= 0; i++) y *= 2.0;"))),
            "3:3: this for loop runs more than 64 iterations, the most that is unrolled");
  EXPECT_EQ(located(shader_error(body("for (int i = 0; i < 4; y + 1.0) i++;"))),
            "3:26: expected an assignment or an increment in the step of 'for', found 'y'");
  EXPECT_EQ(located(shader_error(body("for (y; y < 4.0; y++) {}"))),
            "3:8: expected a declaration or an assignment to start 'for', found 'y'");
  EXPECT_EQ(located(shader_error(body("for (int i = 0; i < 4) y *= 2.0;"))),
            "3:24: expected ';' after the condition of 'for', found ')'");
  EXPECT_EQ(located(shader_error(body("for (int i = 0; i < 4; i++; i++) y *= 2.0;"))),
            "3:29: expected ')' after the step of 'for', found ';'");
  // Errors in a body that never runs are still errors.
  EXPECT_EQ(located(shader_error(body("for (int i = 0; i < 0; i++) y = zzz;"))),
            "3:35: unknown identifier 'zzz'");
  // while and do loops whose condition reads a parameter: unrolled only with a constant one.
  EXPECT_EQ(located(shader_error(body("while (y < 1.0) y *= 2.0;"))),
            "3:10: the condition of this while loop is not a constant: loops are unrolled, so "
            "their trip count must be a constant");
  EXPECT_EQ(located(shader_error(body("do { y *= 2.0; } while (y < 1.0);"))),
            "3:27: the condition of this do loop is not a constant: loops are unrolled, so their "
            "trip count must be a constant");
  EXPECT_EQ(located(shader_error(body("do { y *= 2.0; } until (y < 1.0);"))),
            "3:20: expected 'while' after the body of 'do', found 'until'");
  EXPECT_EQ(located(shader_error(body("if (y > 1.0) break;"))),
            "3:16: 'break' outside a loop (break and continue end a loop's iteration)");
  EXPECT_EQ(located(shader_error(body("continue;"))),
            "3:3: 'continue' outside a loop (break and continue end a loop's iteration)");
}

// --- variables read before they hold a value -------------------------------------------------

TEST(ShaderUndefined, AVariableAssignedOnEveryPathThatReadsItHasNoNaN) {
  // /work/fuzz/probes/p05_elseif.glsl: `y` is assigned in every branch but the one that returns.
  const Program p = shader(R"(
float f(float x) {
    float y;
    if (x < 0.25) {
        y = 4.0 * x;
    } else if (x < 0.5) {
        y = 1.0;
    } else if (x < 0.75) {
        return 2.0 - x;
    } else {
        y = x * x;
    }
    y += 0.5;
    return y;
})");
  EXPECT_EQ(at(p, {0.125}), 1.0);
  EXPECT_EQ(at(p, {0.375}), 1.5);
  EXPECT_EQ(at(p, {0.625}), 1.375);
  EXPECT_EQ(at(p, {1.0}), 1.5);
  const std::string f = formula_of(p);
  EXPECT_EQ(f.find("nan"), std::string::npos) << f;
  EXPECT_EQ(f.find("none"), std::string::npos) << f;
  for (const Instruction& in : p.code)
    EXPECT_FALSE(in.op == ProgramOp::Const && std::isnan(in.value)) << f;
  // Given a value on some paths only: where it has none, reading it is undefined, so it reads as
  // the value the other paths gave it (no NaN, no select).
  const Program q = shader("float f(float x) { float y; if (x > 0.5) y = 2.0 * x; return y; }");
  EXPECT_EQ(at(q, {0.25}), 0.5);
  EXPECT_EQ(formula_of(q), "2 * x");
}

TEST(ShaderUndefined, ReadingAVariableThatHoldsNoValueIsAnError) {
  EXPECT_EQ(located(shader_error("float f(float x) {\n  float y;\n  return y + x;\n}")),
            "3:10: 'y' is read before it is given a value (declared at line 2)");
  EXPECT_EQ(located(shader_error("float f(float x) {\n  float y, z = 1.0;\n  y += x;\n"
                                 "  return y;\n}")),
            "3:3: 'y' is read before it is given a value (declared at line 2)");
  EXPECT_EQ(located(shader_error("float f(float x) {\n  int n;\n  n++;\n  return x;\n}")),
            "3:3: 'n' is read before it is given a value (declared at line 2)");
  EXPECT_EQ(
      located(shader_error("float f(float x) {\n  float y;\n  if (x > 0.0) { float z; y = z; }\n"
                           "  return x;\n}")),
      "3:31: 'z' is read before it is given a value (declared at line 3)");
  // After a return, on no path: not an error.
  EXPECT_EQ(at(shader("float f(float x) { float y; return x; y += 1.0; }"), {2.0}), 2.0);
}

// --- HLSL attributes -------------------------------------------------------------------------

TEST(ShaderAttributes, SkippedBeforeStatements) {
  // /work/fuzz/probes/p04_hlsl_attrs.hlsl.
  const Program p = shader(R"(
inline float f(in float x, const float y)
{
    min16float h = (min16float)x;
    [branch] if (x > y)
        return h * 2.0h;
    [flatten] if (x < 0.25)
    {
        return (float)y;
    }
    [fastopt] [loop] for (int i = 0; i < 2; i++) h += 1.0;
    [call] { return precise_mul(h, y); }
}
float precise_mul(float a, float b) { precise float r = a * b; return r; }
)",
                           "f", {}, "attrs.hlsl");
  EXPECT_EQ(at(p, {0.75, 0.5}), 1.5);
  EXPECT_EQ(at(p, {0.125, 0.5}), 0.5);
  EXPECT_EQ(at(p, {0.375, 0.5}), (0.375 + 2.0) * 0.5);
  EXPECT_EQ(located(shader_error("float f(float x) {\n  [unroll(4 x;\n  return x;\n}")),
            "2:10: '(' is not closed");
  EXPECT_EQ(located(shader_error("float f(float x) {\n  [branch if (x > 0.0) return x;\n"
                                 "  return x;\n}")),
            "2:11: expected ']' to close the attribute at column 3, found 'if'");
}

// --- while and do loops with a constant trip count ---------------------------------------------

TEST(ShaderWhileLoops, UnrolledLikeForLoops) {
  const Program p = shader(R"(
float f(float x) {
  float sum = 0.0, term = 1.0;
  int k = 0;
  while (k < 6) {           // the exponential's series, 6 terms
    sum += term;
    k++;
    term *= x / float(k);
  }
  int n = 0;
  do {                      // runs once although its condition is false at once
    sum *= 2.0;
    n += 10;
  } while (n < 5);
  int m = 0;
  while (true) {            // left by break
    if (m == 3) break;
    sum += 1.0;
    ++m;
  }
  return sum;
}
)");
  const double x = 0.3;
  double series = 0, term = 1;
  for (int k = 0; k < 6; ++k) {
    series += term;
    term *= x / (k + 1);
  }
  EXPECT_NEAR(at(p, {x}), 2 * series + 3, 1e-12);
}

TEST(ShaderConversions, TruncationByIntIsSaidAsSuch) {
  EXPECT_EQ(formula_of(shader("float f(float x) { return float(int(x * 4.0)) * 0.25; }")),
            "(none: it calls trunc (or converts a float to int), which the search's operators "
            "cannot write)");
}

// --- arrays read at constant places ---------------------------------------------------------------

TEST(ShaderArrays, ConstantTablesAndLocalArraysInUnrolledLoops) {
  // fuzz3's h06: a sum of Gaussians from static const tables, read by an unrolled loop.
  const Program p = shader(R"(
static const float kWeight[3] = { 0.25, 0.5, 0.25 };
static const float3 kScale[] = { float3(1.0, 2.0, 3.0), float3(4.0, 5.0, 6.0),
                                 float3(7.0, 8.0, 9.0) };
float f(float r) {
  float sum = 0.0;
  [unroll] for (uint i = 0; i < 3; i++)
    sum += kWeight[i] * exp(-r * r / kScale[i].y);
  float acc[2];
  acc[0] = sum;
  acc[1] = 2.0 * acc[0];
  float w[] = float[](1.0, 10.0);
  acc[1] += w[1];
  return acc[1];
}
)",
                           "f", {}, "test.hlsl");
  const double r = 0.7;
  const double sum = 0.25 * std::exp(-r * r / 2) + 0.5 * std::exp(-r * r / 5) +
                     0.25 * std::exp(-r * r / 8);
  EXPECT_NEAR(at(p, {r}), 2 * sum + 10, 1e-12);
  // Elements merge across branches as variables do.
  const Program q = shader(R"(
float f(float x) {
  float a[2] = {1.0, 2.0};
  if (x > 0.5) a[1] = x;
  return a[0] + a[1];
}
)");
  EXPECT_EQ(at(q, {0.25}), 3.0);
  EXPECT_EQ(at(q, {0.75}), 1.75);
  const auto body = testing::function_with;
  EXPECT_EQ(located(shader_error(body("float a[2] = {1.0, 2.0}; y = a[2];"))),
            "3:33: a subscript of 'a' must be a constant from 0 to 1 (arrays are read at constant "
            "places: loops are unrolled, so their counter is one)");
  EXPECT_EQ(located(shader_error(body("float a[2] = {1.0, 2.0}; y = a;"))),
            "3:32: the array 'a' is used whole: only its elements (a[k]) are values");
  EXPECT_EQ(located(shader_error(body("float a[3] = {1.0, 2.0};"))),
            "3:16: the values of 'a' have 2 components, and 3 elements of float take 3");
  EXPECT_EQ(located(shader_error(body("float a[2] = {1.0, 2.0}; y = a[int(x)];"))),
            "3:33: a subscript of 'a' must be a constant from 0 to 1 (arrays are read at constant "
            "places: loops are unrolled, so their counter is one)");
}

// HLSL reads an array's values as one list of components (fuzz4's r3): a flat table of vectors,
// nested braces and vector values are the same table; a size given must be met exactly.
TEST(ShaderArrays, ValuesFillTheElementsComponentByComponent) {
  for (const char* values : {"{ 1, 2, 3, 4, 5, 6 }", "{ {1, 2, 3}, {4, 5, 6} }",
                             "{ float3(1, 2, 3), float3(4, 5, 6) }"}) {
    const std::string table = std::string("static const float3 k[2] = ") + values + ";\n";
    const Program p = shader(table + "float f(float r) { return r * k[0].z + k[1].x; }", "f", {},
                             "test.hlsl");
    EXPECT_EQ(formula_of(p), "3 * r + 4") << values;
    const Program q = shader("float f(float r) { float3 k[2] = " + std::string(values) +
                                 "; return r * k[1].y; }",
                             "f", {}, "test.hlsl");
    EXPECT_EQ(formula_of(q), "5 * r") << values;
  }
  const Program sized = shader(
      "#define N 3\nstatic const int M = 2;\nstatic const float a[N] = { 1, 2, 4 };\n"
      "static const float b[M + 1] = { 1, 2, 8 };\n"
      "float f(float r) { return r * a[2] + b[2]; }",
      "f", {}, "test.hlsl");
  EXPECT_EQ(formula_of(sized), "4 * r + 8");
  EXPECT_EQ(located(shader_error("static const float k[2] = { 1, 2, 3 };\n"
                                 "float f(float r) { return r * k[1]; }")),
            "1:27: the values of 'k' have 3 components, and 2 elements of float take 2");
  EXPECT_EQ(located(shader_error("static const float3 k[] = { 1, 2, 3, 4 };\n"
                                 "float f(float r) { return r * k[1].x; }")),
            "1:27: the values of 'k' have 4 components, and whole elements of float3 take a "
            "multiple of 3");
  EXPECT_EQ(located(shader_error("static const float k[2][2] = { 1, 2, 3, 4 };\n"
                                 "float f(float r) { return r * k[1][1]; }")),
            "2:31: arrays of arrays are not supported (k)" + testing::kSubsetNote);
  EXPECT_EQ(located(shader_error("static const float k[2] = { 1, r };\n"
                                 "float f(float r) { return r * k[1]; }")),
            "1:32: unknown identifier 'r' in the value of 'k' (it may use the constants declared "
            "before it)");
}

// --- early returns -------------------------------------------------------------------------------

TEST(ShaderReturns, GuardClausesMakeAChainOfSelects) {
  // Each `if (c) return k;` is one select around the rest: 20 of them lower to 20 selects, where
  // a select per return over the result so far repeated it (fuzz3's five_early_returns.glsl was
  // more than 4096 nodes).
  std::string source = "float f(float x) {\n  float s = x;\n";
  for (int k = 1; k <= 20; ++k)
    source += "  if (x > " + std::to_string(k) + ".0) return " + std::to_string(k) + ".0;\n  s *= 0.5;\n";
  source += "  return s;\n}\n";
  const Program p = shader(source);
  EXPECT_EQ(at(p, {0.5}), 0.5 * std::pow(0.5, 20));
  EXPECT_EQ(at(p, {7.5}), 1.0);
  const std::string f = formula_of(p);
  EXPECT_EQ(f.rfind("select(1 - x >= 0, select(2 - x >= 0, select(3 - x >= 0, ", 0), 0u) << f;
  EXPECT_LT(f.size(), 700u) << f;
  // Returns in nested branches and in a loop keep their order: the first taken is the result.
  const Program q = shader(R"(
float f(float x) {
  if (x > 0.0) {
    if (x > 2.0) return 2.0;
    if (x > 1.0) return 1.0;
  } else {
    return -1.0;
  }
  for (int i = 0; i < 3; i++) {
    if (x > 0.25 * float(i + 1)) continue;
    return float(i) + 10.0;
  }
  return 100.0;
}
)");
  EXPECT_EQ(at(q, {3.0}), 2.0);
  EXPECT_EQ(at(q, {1.5}), 1.0);
  EXPECT_EQ(at(q, {-1.0}), -1.0);
  EXPECT_EQ(at(q, {0.1}), 10.0);
  EXPECT_EQ(at(q, {0.3}), 11.0);
  EXPECT_EQ(at(q, {0.6}), 12.0);
  EXPECT_EQ(at(q, {0.9}), 100.0);
}

// --- HLSL's default parameter values ------------------------------------------------------------

TEST(ShaderDefaultParameters, TheLastParametersTakeTheirDefaultsWhereNotGiven) {
  // fuzz3's h10: Unity's FastSign(s, positiveZero = true).
  const char* source = R"(
float FastSign(float s, bool positiveZero = true) {
  return positiveZero ? (s >= 0.0 ? 1.0 : -1.0) : (s > 0.0 ? 1.0 : -1.0);
}
float scale(float x, float k = 2.0, float b = (1.0)) { return x * k + b; }
float f(float x) { return FastSign(x) + 10.0 * FastSign(x, false) + 100.0 * scale(x) +
                          1000.0 * scale(x, 3.0) + 1e4 * scale(x, 3.0, 0.0); }
)";
  const Program p = shader(source, "f", {}, "test.hlsl");
  EXPECT_EQ(at(p, {0.0}), 1.0 - 10.0 + 100.0 * 1.0 + 1000.0 * 1.0 + 0.0);
  EXPECT_EQ(at(p, {1.0}), 1.0 + 10.0 + 100.0 * 3.0 + 1000.0 * 4.0 + 1e4 * 3.0);
  EXPECT_EQ(located(shader_error(std::string(source) +
                                 "float g(float x) { return scale(); }", "g")),
            "8:27: scale takes 1 to 3 arguments, got 0");
}

// --- HLSL's sincos ----------------------------------------------------------------------------

TEST(ShaderSincos, WritesTheSineAndCosineOfScalarsAndVectors) {
  const Program p = shader(R"(
float f(float theta) {
  float s, c;
  sincos(theta, s, c);
  float2 sv, cv;
  sincos(float2(theta, 2.0 * theta), sv, cv);
  return s + 10.0 * c + 100.0 * sv.y + 1000.0 * cv.y;
}
)",
                           "f", {}, "test.hlsl");
  const double t = 0.3;
  EXPECT_NEAR(at(p, {t}),
              std::sin(t) + 10 * std::cos(t) + 100 * std::sin(2 * t) + 1000 * std::cos(2 * t),
              1e-12);
  const auto body = testing::function_with;
  EXPECT_EQ(located(shader_error(body("float s; y = sincos(x, s, y);"))),
            "3:16: sincos returns void: its call is a statement of its own, not a value");
  EXPECT_EQ(located(shader_error(body("float s; sincos(x, s, 2.0);"))),
            "3:25: the cosine, sincos's third argument, writes its argument: it must be a "
            "variable (a local or a parameter, or a member, element or component of one), found "
            "'2.0'");
}

}  // namespace
}  // namespace shaderfit::reference
