// The shader side of the reference language (reference/language.hpp): one GLSL or HLSL function
// compiled to a program, and each construct outside the subset an error at its line and column.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "shaderfit/core/error.hpp"
#include "reference/shader_test_util.hpp"
#include "shaderfit/reference/language.hpp"

namespace shaderfit::reference {
namespace {

using testing::at;
using testing::located;
using testing::shader;
using testing::shader_error;

double smith_g1(double v, double roughness) {
  const double a2 = std::pow(roughness, 4);
  return 2 * v / (v + std::sqrt(a2 + (1 - a2) * v * v));
}

constexpr const char* kSmithGlsl = R"(#version 450
#extension GL_GOOGLE_include_directive : enable
// Smith GGX masking for one direction, alpha = roughness^2.
#define EPSILON 1e-4
const float kOne = 1.0;
uniform float uTime;
in vec2 uv;
out vec4 color;

float G1(float NdotV, float roughness) {
    float a = roughness * roughness;
    float a2 = a * a;
    float NdotV2 = NdotV * NdotV;  /* the cosine squared */
    float denom = NdotV + sqrt(a2 + (kOne - a2) * NdotV2);
    return denom > EPSILON ? 2.0 * NdotV / denom : 0.0;
}

void main() {
    color = vec4(G1(uv.x, uv.y));
}
)";

TEST(ShaderGlsl, SmithG1WithLocalsAndAConditional) {
  const Program p = shader(kSmithGlsl, "G1", {}, "smith.glsl");
  EXPECT_EQ(p.inputs, (std::vector<std::string>{"NdotV", "roughness"}));
  EXPECT_EQ(p.output_names, (std::vector<std::string>{"NdotV", "roughness", "reference"}));
  EXPECT_EQ(p.description, "smith.glsl: G1");
  for (double v = 0.0; v <= 1.0; v += 0.125) {
    for (double r = 0.05; r <= 1.0; r += 0.15) {
      const double want = v + std::sqrt(std::pow(r, 4) + (1 - std::pow(r, 4)) * v * v) > 1e-4
                              ? smith_g1(v, r)
                              : 0.0;
      EXPECT_NEAR(p.evaluate(std::vector<double>{v, r}), want, 1e-15) << v << ", " << r;
    }
  }
  // The variables may name the parameters in another order.
  const Program q = shader(kSmithGlsl, "G1", {"roughness", "NdotV"});
  EXPECT_EQ(q.inputs, (std::vector<std::string>{"roughness", "NdotV"}));
  EXPECT_EQ(q.evaluate(std::vector<double>{0.5, 0.25}), p.evaluate(std::vector<double>{0.25, 0.5}));
}

TEST(ShaderHlsl, SmithG1WithHlslsSpellings) {
  const char* source = R"(
static const float kTwo = 2.0f;
cbuffer Params : register(b0) { float unused; };
Texture2D tex : register(t0);
SamplerState s;
struct PSInput { float4 pos : SV_Position; };

[numthreads(8, 8, 1)]
void cs(uint3 id : SV_DispatchThreadID) {}

inline float SmithG1(in float NdotV, const float roughness)
{
    const float a2 = pow(roughness, 4);
    float k = rsqrt(a2 + (1.0f - a2) * NdotV * NdotV);
    float g = kTwo * NdotV * k / (NdotV * k + 1.0h);
    return saturate(g);
}

float4 main(PSInput input) : SV_Target { return tex.Sample(s, input.pos.xy); }
)";
  const Program p = shader(source, "SmithG1", {}, "smith.hlsl");
  for (const double v : {0.01, 0.3, 0.9}) {
    for (const double r : {0.1, 0.5, 1.0})
      EXPECT_NEAR(p.evaluate(std::vector<double>{v, r}), smith_g1(v, r), 1e-15) << v << ", " << r;
  }
}

TEST(ShaderGlsl, BranchesReturnsAndInlinedCalls) {
  const char* source = R"(
#define HALF 0.5
const float kLimit = 2.0 * HALF;  // 1
float sq(float x) { return x * x; }
float helper(float x, float y) {
  if (x > y) return sq(x - y);
  return -sq(y - x);
}
float f(float x, float t) {
  float y = 0.0, z;
  if (x < 0.0) {
    y = -x;
    if (t > HALF) return 100.0;
  } else if (x < kLimit) {
    y = helper(x, t);
    y *= 2.0;
  } else {
    return x + t;
    y = 7.0;  // after the return: no effect
  }
  z = y + 1.0;
  z += t; z -= 1.0; z /= 2.0;
  y++;
  return z + y * 0.0;
}
)";
  const Program p = shader(source, "f");
  auto g = [](double x, double t) {
    double y = 0;
    if (x < 0) {
      y = -x;
      if (t > 0.5) return 100.0;
    } else if (x < 1) {
      y = 2 * (x > t ? (x - t) * (x - t) : -((t - x) * (t - x)));
    } else {
      return x + t;
    }
    double z = y + 1.0;
    z += t;
    z -= 1.0;
    z /= 2.0;
    y += 1;
    return z + y * 0.0;
  };
  for (const double x : {-0.7, 0.2, 0.9, 1.5})
    for (const double t : {0.1, 0.6})
      EXPECT_EQ(p.evaluate(std::vector<double>{x, t}), g(x, t)) << x << ", " << t;
}

TEST(ShaderGlsl, BuiltinsIntegersAndCasts) {
  struct Case {
    const char* body;
    double x, want;
  };
  static volatile double read_at_run_time = 0.375;  // std:: functions as the library computes them
  const double x = read_at_run_time;
  const Case cases[] = {
      {"mix(1.0, 3.0, x)", x, 1.0 * (1 - x) + 3.0 * x},
      {"lerp(1.0, 3.0, x)", x, 1.0 + x * 2.0},
      {"smoothstep(0.0, 0.5, x)", x, 0.84375},
      {"step(0.5, x)", x, 0.0},
      {"fract(-x)", x, 0.625},
      {"frac(x + 2.0)", x, x},
      {"mod(-x, 0.25)", x, 0.125},    // GLSL: x - y floor(x / y)
      {"fmod(-x, 0.25)", x, -0.125},  // HLSL and C: truncated
      {"atan(x, -1.0)", x, std::atan2(x, -1.0)},
      {"atan2(x, -1.0)", x, std::atan2(x, -1.0)},
      {"atan(x)", x, std::atan(x)},
      {"radians(180.0) + degrees(x)", x,
       180.0 * (std::numbers::pi / 180.0) + x * (180.0 / std::numbers::pi)},
      {"clamp(x, 0.5, 1.0)", x, 0.5},
      {"inversesqrt(x) * rsqrt(x)", x, (1 / std::sqrt(x)) * (1 / std::sqrt(x))},
      {"rcp(x)", x, 1 / x},
      {"exp2(x) + log2(x) + pow(x, 2.4)", x, std::exp2(x) + std::log2(x) + std::pow(x, 2.4)},
      {"fma(x, 2.0, 1.0) + mad(x, 2.0, 1.0)", x, 3.5},
      {"sign(-x) + abs(-x) + min(x, 0.1) + max(x, 0.1)", x, -1 + x + 0.1 + x},
      {"floor(x * 10.0) + ceil(x) + trunc(-1.5) + round(2.5)", x, 3.0 + 1.0 - 1.0 + 3.0},
      {"float(7 / 2) + float(7) / 2.0", x, 3.0 + 3.5},  // integer division truncates
      {"(float)(-7 / 2) + int(-x * 10.0)", x, -3.0 - 3.0},
      {"x > 0.1 && x < 0.2 || !(x > 0.3) ? 1.0 : 2.0", x, 2.0},
      {"0x10 + 010 + 2u + 1.5f + 1.0lf", x, 16 + 8 + 2 + 2.5},
      {"true ? x : 0.0", x, x},
  };
  for (const Case& c : cases) {
    const std::string source = std::string("float f(float x) {\n  return ") + c.body + ";\n}\n";
    EXPECT_EQ(shader(source, "f").evaluate(std::vector<double>{c.x}), c.want) << c.body;
  }
  const Program ints = shader(R"(
float f(float x) {
  int n = 7;
  const int k = 2;
  n /= k;         // 3
  int m = x * 10.0;  // truncated: 3
  bool b = x;
  return float(n * 10 + m) + float(b);
})",
                              "f");
  EXPECT_EQ(ints.evaluate(std::vector<double>{x}), 34.0);
}

TEST(ShaderErrors, ConstructsOutsideTheSubsetAtTheirLineAndColumn) {
  const auto body = testing::function_with;
  const std::string& more = testing::kSubsetNote;
  EXPECT_EQ(located(shader_error(body("imat3 m;"))),
            "3:3: unknown type 'imat3' (float, half, double, int or bool)");
  EXPECT_EQ(located(shader_error(body("y = int2x2(1, 2, 3, 4)[0].x;"))),
            "3:7: matrix types are not supported (int2x2)" + more);
  EXPECT_EQ(located(shader_error(body("float s, c; sinecos(x, s, c);"))),
            "3:15: unknown function 'sinecos' (did you mean sincos?)");
  EXPECT_EQ(located(shader_error(body("y = y.foo;"))),
            "3:9: '.foo' of a float: only structs have members");
  EXPECT_EQ(located(shader_error(body("y = texture(s, vec2(x)).r;"))),
            "3:7: textures are not supported (texture)" + more);
  EXPECT_EQ(located(shader_error(body("y = t.Sample(s, x);"))),
            "3:8: textures are not supported (.Sample)" + more);
  EXPECT_EQ(located(shader_error(body("float a[4][2];"))),
            "3:13: arrays of arrays are not supported ([)" + more);
  EXPECT_EQ(located(shader_error(body("switch (int(y)) { case 0: y = 1.0; }"))),
            "3:3: switch statements are not supported (switch)" + more);
  EXPECT_EQ(located(shader_error(body("if (y < 0.0) discard;"))),
            "3:16: discard statements are not supported (discard)" + more);
  EXPECT_EQ(located(shader_error(body("y = y ^ 2;"))),
            "3:9: bitwise operators are not supported ('^')");
  EXPECT_EQ(located(shader_error(body("y = smoothstp(0.0, 1.0, y);"))),
            "3:7: unknown function 'smoothstp' (did you mean smoothstep?)");
  EXPECT_EQ(located(shader_error(body("y = zzzqqq(y);"))),
            "3:7: unknown function 'zzzqqq' (neither a built-in of the subset nor a function of "
            "this file)");
  EXPECT_EQ(located(shader_error(body("y = clamp(y, 0.0);"))),
            "3:7: clamp takes 3 arguments, got 2");
  EXPECT_EQ(located(shader_error(body("y = w;"))), "3:7: unknown identifier 'w'");
  EXPECT_EQ(located(shader_error(body("float rough = x; y = 2.0 * roughh;"))),
            "3:30: unknown identifier 'roughh' (did you mean rough?)");
  EXPECT_EQ(located(shader_error(body("struct S { float a; };"))),
            "3:3: structs declared inside functions are not supported (struct)" + more);
  EXPECT_EQ(located(shader_error(body("#ifdef FOO"))),
            "3:3: #ifdef is not closed: its #endif is missing");
  EXPECT_EQ(located(shader_error(body("const float k;"))), "3:15: the constant 'k' needs a value");
  EXPECT_EQ(located(shader_error(body("float y = 2.0;"))),
            "3:9: 'y' is already declared in this scope (line 2)");
}

TEST(ShaderErrors, SignaturesFilesAndCalls) {
  const std::string& more = testing::kSubsetNote;
  EXPECT_EQ(located(shader_error("float f(float x, out float y) { y = x; return x; }")),
            "1:18: parameter 'y' of f is out: the reference's parameters are its inputs and its "
            "one result is the float it returns (call f from a function that returns the value)");
  EXPECT_EQ(located(shader_error("float f(mat2 p) { return p[0].x; }")),
            "1:14: parameter 'p' is a mat2: the function's parameters are the reference's "
            "variables, each a float (give the components as floats, or call f from a function "
            "that takes them)");
  EXPECT_EQ(located(shader_error("float f(sampler2D s) { return 0.0; }")),
            "1:9: textures are not supported (sampler2D)" + more);
  EXPECT_EQ(located(shader_error("float f(int n) { return 1.0; }")),
            "1:13: parameter 'n' is not a float: the function's parameters are the reference's "
            "variables (float, half or double)");
  EXPECT_EQ(located(shader_error("float f(float x) {\n  if (x > 0.0) return x;\n}")),
            "3:1: function 'f' can reach its end without returning a value");
  EXPECT_EQ(located(shader_error("float f(float x) { x = 1.0; }")),
            "1:29: function 'f' ends without returning a value");
  EXPECT_EQ(located(shader_error("void f(float x) { }")),
            "1:1: function 'f' returns void: a reference returns a float");
  EXPECT_EQ(located(shader_error("float g(float x);\nfloat f(float x) { return g(x) + 1.0; }\n"
                                 "float g(float x) { return f(x); }")),
            "3:27: recursion is not supported (f -> g -> f)" + more);
  EXPECT_EQ(located(shader_error("float f(float x) { return f(x); }")),
            "1:27: recursion is not supported (f -> f)" + more);
  EXPECT_EQ(located(shader_error("float g(float a, float b) { return a; }\n"
                                 "float f(float x) { return g(x); }")),
            "2:27: g takes 2 arguments, got 1");
  EXPECT_EQ(located(shader_error("#include \"common.glsl\"\nfloat f(float x) { return x; }")),
            "1:1: #include is not supported (\"common.glsl\"): the reference is read from its one "
            "file" +
                more);
  EXPECT_EQ(located(shader_error("uniform float t;\nfloat f(float x) { return x * t; }")),
            "2:31: uniforms are not supported (t)" + more);
  EXPECT_EQ(located(shader_error("float f(float x) { return x; }\nfloat f(float x, float y) "
                                 "{ return y; }")),
            "2:7: function 'f' is defined 2 times (f(float x) at line 1, f(float x, float y) at "
            "line 2): the variables pick one, by its parameters' names");
  // Of overloads named alike, the one whose parameters are floats (Unity's SRGBToLinear).
  const std::string srgb =
      "float s(float c) { return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4); }\n"
      "float3 s(float3 c) { return float3(s(c.r), s(c.g), s(c.b)); }";
  EXPECT_NEAR(at(shader(srgb, "s", {}, "color.hlsl"), {0.5}), std::pow(0.555 / 1.055, 2.4), 1e-15);
  // The variables pick an overload.
  const std::string overloads =
      "float f(float x, float k) { return x / (x + k); }\nfloat f(float x) { return f(x, 1.0); }";
  EXPECT_EQ(at(shader(overloads, "f", {"x"}), {1.0}), 0.5);
  EXPECT_EQ(at(shader(overloads, "f", {"k", "x"}), {3.0, 1.0}), 0.25);
  EXPECT_EQ(located(shader_error("float f(float x) { return x;")), "1:18: '{' is not closed");
  EXPECT_EQ(located(shader_error("float f(float x) { return x @ 2; }")),
            "1:29: unexpected character '@'");

  const Error missing =
      shader_error("float G1(float v) { return v; }\nfloat D(float v) { return v; }", "G2");
  EXPECT_EQ(missing.where().source, "test.glsl");
  EXPECT_EQ(missing.where().line, 0);
  EXPECT_EQ(missing.message(), "function 'G2' is not in test.glsl (its functions: G1, D)");
  try {
    (void)shader("float f(float x, float y) { return x; }", "f", {"x", "z"});
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(located(e), "1:7: the variables (x, z) are not the parameters of f (x, y)");
  }
}

TEST(ShaderGlsl, TheOneFunctionOfAFileNeedsNoName) {
  const Program p = shader("float only(float x) { return x * 2.0; }", "");
  EXPECT_EQ(p.evaluate(std::vector<double>{1.5}), 3.0);
  EXPECT_EQ(p.description, "test.glsl: only");
}

TEST(ShaderErrors, HostileInputsStayWithinLimits) {
  // Nesting: blocks and parentheses.
  const std::string deep =
      "float f(float x) " + std::string(300, '{') + " return x; " + std::string(300, '}');
  EXPECT_NE(shader_error(deep).message().find("nested more than 256 levels"), std::string::npos);
  // Inlining that doubles at every level stops at the program size limit.
  std::string doubling = "float f0(float x) { return x * 1.5 + 1.0; }\n";
  for (int i = 1; i <= 40; ++i) {
    doubling += "float f" + std::to_string(i) + "(float x) { return f" + std::to_string(i - 1) +
                "(x) + f" + std::to_string(i - 1) + "(x * 0.5); }\n";
  }
  EXPECT_NE(shader_error(doubling, "f40").message().find("the reference is too large"),
            std::string::npos);
}

}  // namespace
}  // namespace shaderfit::reference
