// The shader front end's vectors (language_expression.cpp, language_shader.cpp): vec2-vec4 and
// float2-float4 built, swizzled, subscripted, combined component by component and by the
// geometric built-ins, held in variables, constants and helpers' parameters and results, inside
// a function whose inputs and result are floats. Each is checked by the program's values at
// points against the C++ it means, and each bad input by its message and location.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "reference/shader_test_util.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/expr/print.hpp"
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

TEST(ShaderVectors, ConstructorsSwizzlesAndSubscripts) {
  const Program p = shader(R"(
float f(float x, float y) {
  vec3 v = vec3(x, y, 2.0);
  vec4 w = vec4(v.zy, 1.0, x);   // (2, y, 1, x)
  vec2 s = vec2(3.0);            // (3, 3)
  float3 h = float3(w.wzy);      // (x, 1, y)
  return v.x + 10.0 * w.y + 100.0 * s.g + 1000.0 * h[2] + 1e4 * w[0] + 1e5 * v.b;
})");
  const double x = 0.25, y = 0.5;
  EXPECT_DOUBLE_EQ(at(p, {x, y}), x + 10 * y + 300 + 1000 * y + 2e4 + 2e5);
}

TEST(ShaderVectors, ArithmeticIsComponentwiseAndScalarsBroadcast) {
  const Program p = shader(R"(
float f(float a, float b) {
  float3 u = float3(a, b, 1.0);
  float3 v = 2.0 * u - float3(0.5, 0.25, 0.0);
  v *= u;                 // (2a^2 - a/2, 2b^2 - b/4, 2)
  v += 1.0;
  float3 w = -v / 2.0;
  return w.x + w.y * 10.0 + w.z * 100.0;
})");
  const double a = 0.3, b = 0.7;
  const double vx = 2 * a * a - 0.5 * a + 1, vy = 2 * b * b - 0.25 * b + 1, vz = 3;
  EXPECT_NEAR(at(p, {a, b}), -vx / 2 - 10 * vy / 2 - 100 * vz / 2, 1e-12);
}

TEST(ShaderVectors, GeometricBuiltIns) {
  const Program p = shader(R"(
float f(float x, float y) {
  vec3 n = normalize(vec3(x, y, 1.0));
  vec3 l = vec3(0.0, 0.6, 0.8);
  vec3 c = cross(n, l);
  vec3 r = reflect(-l, n);
  return dot(n, l) + 10.0 * length(c) + 100.0 * distance(r, l) + 1000.0 * length(x);
})");
  const double x = 0.4, y = -0.3;
  const double len = std::sqrt(x * x + y * y + 1);
  const double n[3] = {x / len, y / len, 1 / len}, l[3] = {0, 0.6, 0.8};
  const double d = n[0] * l[0] + n[1] * l[1] + n[2] * l[2];
  const double c[3] = {n[1] * l[2] - n[2] * l[1], n[2] * l[0] - n[0] * l[2],
                       n[0] * l[1] - n[1] * l[0]};
  double r[3], dist2 = 0;
  for (int i = 0; i < 3; ++i) {
    r[i] = -l[i] + 2 * d * n[i];  // reflect(-l, n) = -l - 2 dot(n, -l) n
    dist2 += (r[i] - l[i]) * (r[i] - l[i]);
  }
  const double want = d + 10 * std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]) +
                      100 * std::sqrt(dist2) + 1000 * std::abs(x);
  EXPECT_NEAR(at(p, {x, y}), want, 1e-12);
}

TEST(ShaderVectors, ScalarBuiltInsApplyComponentByComponent) {
  const Program p = shader(R"(
float f(float x) {
  float3 v = float3(x, -x, 2.0 * x);
  float3 s = saturate(v);
  float3 m = max(v, 0.25);
  float3 q = pow(abs(v), 2);
  float3 t = lerp(v, float3(1.0, 1.0, 1.0), 0.5);
  return dot(s, float3(1.0, 10.0, 100.0)) + dot(m, float3(1e3, 1e4, 1e5)) + q.y * 1e6 + t.z * 1e7;
}
)",
                           "f", {}, "test.hlsl");
  const double x = 0.375;
  const double want = (x + 0 + 100 * std::min(2 * x, 1.0)) +
                      (1e3 * std::max(x, 0.25) + 1e4 * 0.25 + 1e5 * std::max(2 * x, 0.25)) +
                      1e6 * x * x + 1e7 * (2 * x + 0.5 * (1 - 2 * x));
  EXPECT_NEAR(at(p, {x}), want, 1e-6);
}

TEST(ShaderVectors, ComponentWritesAndBranchesMerge) {
  const Program p = shader(R"(
float f(float x) {
  vec3 v;
  v.x = x;
  v.yz = vec2(2.0, 3.0);
  v[2] += 1.0;               // (x, 2, 4)
  if (x > 0.5) v.zx = v.xz;  // (4, 2, x) above one half
  v.y++;
  return v.x + 10.0 * v.y + 100.0 * v.z;
})");
  EXPECT_DOUBLE_EQ(at(p, {0.25}), 0.25 + 30 + 400);
  EXPECT_DOUBLE_EQ(at(p, {0.75}), 4 + 30 + 75);
}

TEST(ShaderVectors, HelpersTakeAndReturnVectorsAndWriteOutVectors) {
  const Program p = shader(R"(
static const float3 kLuma = float3(0.2126, 0.7152, 0.0722);
#define WHITE float3(1.0, 1.0, 1.0)
float3 tint(float3 c, float k) { return lerp(WHITE, c, k); }
void split(float3 c, out float2 rg, inout float b) { rg = c.rg; b += c.b; }
float f(float r, float k) {
  float3 c = tint(float3(r, 0.5, 0.25), k);
  float2 rg;
  float b = 1.0;
  split(c, rg, b);
  return dot(c, kLuma) + 10.0 * (rg.x + rg.y) + 100.0 * b;
}
)",
                           "f", {}, "test.hlsl");
  const double r = 0.8, k = 0.3;
  auto mixed = [&](double c) { return 1 + k * (c - 1); };
  const double c[3] = {mixed(r), mixed(0.5), mixed(0.25)};
  const double want = 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2] + 10 * (c[0] + c[1]) +
                      100 * (1 + c[2]);
  EXPECT_NEAR(at(p, {r, k}), want, 1e-12);
}

TEST(ShaderVectors, HlslCastsAndTruncation) {
  const Program p = shader(R"(
float f(float x) {
  float3 v = (float3)x;          // (x, x, x)
  float2 t = float3(x, 2.0, 3.0);  // truncated: (x, 2)
  float s = float(v * 2.0);      // the first component
  return v.z + 10.0 * t.y + 100.0 * s + 1000.0 * x.x + 1e4 * x.xxx.z;
}
)",
                           "f", {}, "test.hlsl");
  const double x = 0.5;
  EXPECT_DOUBLE_EQ(at(p, {x}), x + 20 + 100 * 2 * x + 1000 * x + 1e4 * x);
}

TEST(ShaderVectors, DotWithConstantComponentsCostsNoMore) {
  // A zero component adds nothing, a one multiplies by nothing: the lowered formula has no
  // `+ 0` or `* 1` (fuzz case h03: dot(float3(LoV, NoL, 0), float3(1, -NoV, 0))).
  const Program p = shader(R"(
float f(float LoV, float NoL, float NoV) {
  return dot(float3(LoV, NoL, 0), float3(1, -NoV, 0));
}
)",
                           "f", {}, "test.hlsl");
  EXPECT_EQ(formula_of(p), "LoV - NoL * NoV");
  EXPECT_DOUBLE_EQ(at(p, {0.5, 0.25, 0.75}), 0.5 - 0.25 * 0.75);
  // A zero component times anything is nothing (fuzz3's Kajiya-Kay: normalize(T + N * shift)
  // with T and N constant axes).
  EXPECT_EQ(formula_of(shader("float f(float s) { return dot(vec3(0.0, 0.0, 1.0), vec3(s, 2.0 * "
                              "s, 3.0 * s)); }")),
            "3 * s");
}

TEST(ShaderVectors, TwoLobePhaseFunctionBlendedByADot) {
  // /work/fuzz/shaders/g05_hg.glsl: two Henyey-Greenstein lobes weighted by dot(vec2, vec2).
  const Program p = shader(R"(
#define INV_4PI 0.07957747154594767
float hg(float cosTheta, float g) {
    float g2 = g * g;
    float denom = 1. + g2 - 2.*g*cosTheta;
    return INV_4PI * (1. - g2) / pow(denom, 1.5);
}
float doubleHG(float cosTheta, float g1, float g2, float t) {
    float p1 = hg(cosTheta, g1);
    float p2 = hg(cosTheta, g2);
    return dot(vec2(p1, p2), vec2(1.0 - t, t));
}
)",
                           "doubleHG");
  auto hg = [](double c, double g) {
    return (1 - g * g) / (4 * std::numbers::pi * std::pow(1 + g * g - 2 * g * c, 1.5));
  };
  const double c = 0.3, g1 = 0.7, g2 = -0.2, t = 0.4;
  EXPECT_NEAR(at(p, {c, g1, g2, t}), (1 - t) * hg(c, g1) + t * hg(c, g2), 1e-12);
}

TEST(ShaderVectors, BadInputsAtTheirLineAndColumn) {
  const auto body = testing::function_with;
  EXPECT_EQ(located(shader_error(body("vec3 v = vec2(x, x);"))),
            "3:10: cannot give a float2 to 'v', a float3");
  EXPECT_EQ(located(shader_error(body("y = (vec2(x) + vec3(x)).x;"))),
            "3:16: '+' of vectors of different sizes (float2 and float3)");
  EXPECT_EQ(located(shader_error(body("y = float(vec2(x) < vec2(y));"))),
            "3:21: '<' of vectors is not supported (compare or combine their components)");
  EXPECT_EQ(located(shader_error(body("y = vec2(x).z;"))),
            "3:15: '.z' of a float2: it has no 'z'");
  EXPECT_EQ(located(shader_error(body("y = vec3(x)[3];"))),
            "3:14: a subscript of a float3 must be a constant from 0 to 2");
  EXPECT_EQ(located(shader_error(body("vec3 v = vec3(x, x);"))),
            "3:12: vec3(...) is given 2 components, and has 3");
  EXPECT_EQ(located(shader_error(body("vec3 v = vec3(x); v.xx = vec2(1.0);"))),
            "3:23: '.xx' writes a component twice");
  EXPECT_EQ(located(shader_error(body("y = dot(vec2(x), vec3(x));"))),
            "3:7: the arguments of dot have different sizes (float2 and float3)");
  EXPECT_EQ(located(shader_error(body("y = cross(vec2(x), vec2(x)).x;"))),
            "3:7: cross takes two 3-component vectors, got float2");
  EXPECT_EQ(located(shader_error(body("if (vec2(x)) y = 1.0;"))),
            "3:3: the condition of 'if' is a float2, not a scalar");
  EXPECT_EQ(located(shader_error(body("y = y.color;"))),
            "3:9: '.color' of a float: only structs have members");
  EXPECT_EQ(located(shader_error(body("y = y[0];"))),
            "3:8: a subscript of a scalar: arrays are not supported");
  EXPECT_EQ(located(shader_error("vec3 f(float x) { return vec3(x); }")),
            "1:1: function 'f' returns a vec3: a reference returns a float (return one "
            "component, or call it from a function that does)");
  EXPECT_EQ(located(shader_error("float f(vec2 p) { return p.x; }")),
            "1:14: parameter 'p' is a float2: the function's parameters are the reference's "
            "variables, each a float (give the components as floats, or call f from a function "
            "that takes them)");
  EXPECT_EQ(located(shader_error("float g(vec3 v) { return v.x; }\n"
                                 "float f(float x) { return g(vec2(x)); }")),
            "2:27: cannot give a float2 to the parameter 'v' of g, a float3");
}

// An out or inout argument may be a member, an array's element or a vector's components
// (`sincos(phi, dir.y, dir.x)`); the rest of the variable keeps its value.
TEST(ShaderVectors, OutArgumentsIntoComponentsMembersAndElements) {
  const Program p = shader(R"(
struct R { float s; float c; };
void Scale(inout float2 v, float k) { v *= k; }
void Five(out float v) { v = 5.0; }
float f(float x) {
  R r;
  sincos(x, r.s, r.c);
  float2 d;
  sincos(x, d.y, d.x);
  float3 a = float3(x, 1.0, 2.0);
  Scale(a.yz, 3.0);
  float w[2] = { 1.0, 2.0 };
  Five(w[1]);
  return r.s + 10.0 * r.c + 100.0 * d.x + 1000.0 * d.y + a.x + a.y + a.z + w[0] + w[1] * x;
})",
                           "f", {}, "test.hlsl");
  const double x = 0.3;
  EXPECT_NEAR(at(p, {x}), std::sin(x) + 10 * std::cos(x) + 100 * std::cos(x) + 1000 * std::sin(x) +
                              x + 3 + 6 + 1 + 5 * x,
              1e-12);
}

// Overloads taking as many arguments are told apart by the arguments' types (fuzz4's r7):
// Unreal's Square and Pow5 for float and float3 side by side, in either order.
TEST(ShaderVectors, OverloadsOfOneArityPickedByTheArgumentsTypes) {
  const Program p = shader(R"(
float SumXY(float2 v) { return v.x + v.y; }
float SumXY(float x) { return 10.0 * x; }
float3 Square(float3 x) { return x * x; }
float Square(float x) { return x * x; }
void Set(out float2 v) { v = float2(1.0, 2.0); }
void Set(out float w) { w = 3.0; }
float f(float a) {
  float2 v;
  float w;
  Set(v);
  Set(w);
  return SumXY(a) + SumXY(float2(a, 1.0)) + Square(a) + Square(float3(a, 2.0, 3.0)).z + v.y + w;
})",
                           "f", {}, "test.hlsl");
  const double a = 0.5;
  EXPECT_DOUBLE_EQ(at(p, {a}), 10 * a + a + 1 + a * a + 9 + 2 + 3);
  EXPECT_EQ(located(shader_error("float G(float2 x) { return x.x; }\n"
                                 "float G(float3 x) { return x.z; }\n"
                                 "float f(float a) { return G(a); }")),
            "3:27: the call G(float) fits two of its overloads alike (G(float2) at line 1, "
            "G(float3) at line 2)");
  EXPECT_EQ(located(shader_error("float G(float2 x) { return x.x; }\n"
                                 "float G(float3 x) { return x.z; }\n"
                                 "float f(float a) { return G(float4(a, a, a, a)); }")),
            "3:27: the call G(float4) fits none of its overloads (G(float2) at line 1, G(float3) "
            "at line 2)");
}

}  // namespace
}  // namespace shaderfit::reference
