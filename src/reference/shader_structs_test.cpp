// The shader front end's structs (language_shader_file.cpp, language_shader.cpp,
// language_expression.cpp): declared at file scope, held in locals and arrays, read and written
// member by member (nested, with swizzles), built by GLSL's constructors, HLSL's casts and braces,
// passed to helpers and returned by them, merged by branches. Each is checked by the program's
// values at points against the C++ it means, and each bad input by its message and location.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "reference/shader_test_util.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/reference/language.hpp"

namespace shaderfit::reference {
namespace {

using testing::at;
using testing::formula_of;
using testing::kSubsetNote;
using testing::located;
using testing::shader;
using testing::shader_error;

// Unreal's habit: a context struct filled by a helper through inout, read by another.
TEST(ShaderStructs, AContextFilledByOneHelperAndReadByAnother) {
  const Program p = shader(R"(
struct BxDFContext {
  float NoV;
  float NoL, VoH;
  float NoH;
};
void Init(inout BxDFContext Context, float NoV, float NoL) {
  Context.NoV = NoV;
  Context.NoL = NoL;
  Context.VoH = 0.5 * (NoV + NoL);
  Context.NoH = Context.VoH * Context.VoH;
}
float Lobe(BxDFContext C) { return C.NoV * C.NoL + C.NoH; }
float f(float NoV, float NoL) {
  BxDFContext Context;
  Init(Context, NoV, NoL);
  return Lobe(Context) + Context.VoH;
})",
                           "f", {}, "test.hlsl");
  const double v = 0.3, l = 0.8, h = 0.5 * (v + l);
  EXPECT_DOUBLE_EQ(at(p, {v, l}), v * l + h * h + h);
}

// Filament's habit: a const struct parameter and a GLSL constructor.
TEST(ShaderStructs, GlslConstructorAndConstParameter) {
  const Program p = shader(R"(
struct PixelParams {
  highp float roughness;
  float f0;
  vec3 diffuse;
};
float D(const PixelParams pixel, float NoH) {
  float a = pixel.roughness * pixel.roughness;
  return a / (1.0 + NoH * pixel.diffuse.g) + pixel.f0;
}
float f(float NoH, float roughness) {
  PixelParams pixel = PixelParams(roughness, 0.04, vec3(0.25, 0.5, 1.0));
  return D(pixel, NoH);
})");
  const double n = 0.7, r = 0.4;
  EXPECT_DOUBLE_EQ(at(p, {n, r}), r * r / (1 + n * 0.5) + 0.04);
  EXPECT_EQ(formula_of(p), "roughness * roughness / (1 + 0.5 * NoH) + 0.04");
}

// HLSL: (S)0, braces, nested structs with swizzles, compound assignments and increments of
// members, a struct returned by a helper.
TEST(ShaderStructs, CastsBracesNestingAndReturns) {
  const Program p = shader(R"(
struct Inner { float2 ab; float c; };
struct Ctx {
  float u, v;
  float3 tint : COLOR0;
  nointerpolation Inner inner;
};
Ctx Make(float u, float v) {
  Ctx c = (Ctx)0;
  c.u = u;
  c.v = v;
  c.tint = float3(1, 0.5, 0.25);
  c.inner.ab.y = 2.0;
  c.inner.c += 1.0;
  c.inner.c++;
  return c;
}
float f(float u, float v) {
  Ctx a = Make(u, v);
  Ctx b = { u, v, 1, 1, 1, { 0, 3 }, 4 };
  Ctx pair[2] = { a, b };
  pair[1].inner.ab.x *= 10.0;
  return a.u * a.v + a.tint.g + a.inner.ab.y + a.inner.c + 100.0 * pair[1].inner.ab.y +
         1000.0 * pair[1].inner.c + pair[0].inner.ab.x;
})",
                           "f", {}, "test.hlsl");
  const double u = 0.3, v = 0.6;
  EXPECT_DOUBLE_EQ(at(p, {u, v}), u * v + 0.5 + 2 + 2 + 300 + 4000 + 0);
}

// Branches and ?: merge whole structs member by member; a helper's inout struct is written back
// where the call is taken.
TEST(ShaderStructs, BranchesMergeStructsMemberByMember) {
  const Program p = shader(R"(
struct S { float a; float2 b; };
void Scale(inout S s, float k) { s.a *= k; s.b = s.b * k; }
float f(float x, float y) {
  S p = S(x, vec2(1.0, y));
  S q = S(y, vec2(2.0));
  if (x > 0.5) Scale(p, 2.0);
  S r = y > 0.5 ? p : q;
  return r.a + 10.0 * r.b.x + 100.0 * r.b.y;
})");
  auto want = [](double x, double y) {
    double a = x, b0 = 1, b1 = y;
    if (x > 0.5) a *= 2, b0 *= 2, b1 *= 2;
    return y > 0.5 ? a + 10 * b0 + 100 * b1 : y + 10 * 2 + 100 * 2;
  };
  for (const double x : {0.25, 0.75})
    for (const double y : {0.25, 0.75}) EXPECT_DOUBLE_EQ(at(p, {x, y}), want(x, y)) << x << y;
}

// Unity's Color.hlsl: the LogC parameters as a file-scope struct constant in braces; GLSL's as a
// constructor.
TEST(ShaderStructs, FileScopeStructConstants) {
  const Program hlsl = shader(R"(
struct ParamsLogC { float cut; float a, b, c, d, e, f; };
static const ParamsLogC LogC = {
  0.011361, // cut
  5.555556, 0.047996, 0.244161, 0.386036, 5.301883, 0.092819
};
float f(float x) {
  if (x > LogC.cut) return LogC.c * log10(max(LogC.a * x + LogC.b, 0.0)) + LogC.d;
  return LogC.e * x + LogC.f;
})",
                              "f", {}, "color.hlsl");
  EXPECT_NEAR(at(hlsl, {0.5}), 0.244161 * std::log10(5.555556 * 0.5 + 0.047996) + 0.386036, 1e-12);
  EXPECT_NEAR(at(hlsl, {0.01}), 5.301883 * 0.01 + 0.092819, 1e-15);
  const Program glsl = shader(R"(
struct Falloff { float radius; vec2 scale; };
const Falloff kFalloff = Falloff(2.0, vec2(0.5, 3.0));
float f(float d) { return kFalloff.scale.y * d / kFalloff.radius + kFalloff.scale.x; })");
  EXPECT_DOUBLE_EQ(at(glsl, {0.5}), 3 * 0.5 / 2 + 0.5);
}

TEST(ShaderStructs, AStructNeverUsedIsNeverRead) {
  const Program p = shader(R"(
struct Unused { float3x3 m; Texture2D t; };
float f(float x) { return 2.0 * x; })");
  EXPECT_DOUBLE_EQ(at(p, {0.5}), 1.0);
}

TEST(ShaderStructs, BadInputIsOneClearError) {
  const std::string s = "struct S { float a; float b; };\n";
  auto error = [&](const std::string& body, const std::string& head = "float f(float x)") {
    return located(shader_error(s + head + " {\n" + body + "\n}\n"));
  };
  EXPECT_EQ(error("S s; s.c = x; return s.a;"), "3:8: 'S' has no member 'c' (its members: a, b)");
  EXPECT_EQ(error("S s = (S)x; return s.q;"), "3:22: 'S' has no member 'q' (its members: a, b)");
  EXPECT_EQ(error("S s = (S)x; return s + x;"),
            "3:22: '+' of a S: a struct is not a number (use its members)");
  EXPECT_EQ(error("S s = (S)x; return -s;"),
            "3:21: '-' of a S: a struct is not a number (use its members)");
  EXPECT_EQ(error("S s = (S)x; return sqrt(s);"),
            "3:20: sqrt of a S: a struct is not a number (use its members)");
  EXPECT_EQ(error("S s = (S)x; return s[0];"),
            "3:21: a subscript of a S: a struct has members, not components");
  EXPECT_EQ(error("S s = (S)x; return s;"), "3:13: cannot give a S to the result of f, a float");
  EXPECT_EQ(error("S s = (S)x; return x > 0.0 ? s : x;"),
            "3:28: the branches of '?' have different types (S and float)");
  EXPECT_EQ(error("S s = (S)x; if (s) return 1.0; return x;"),
            "3:13: the condition of 'if' is a S, not a scalar");
  EXPECT_EQ(error("S s = {x}; return s.a;"),
            "3:7: the values in braces for 's' have 1 component, and a S has 2");
  EXPECT_EQ(error("S s = S(x); return s.a;"), "3:7: S(...) is given 1 value, and has 2 members");
  EXPECT_EQ(error("S s; return s.a;"), "3:13: 's' is read before it is given a value (declared at line 3)");
  EXPECT_EQ(error("return x.foo;"), "3:10: '.foo' of a float: only structs have members");
  EXPECT_EQ(error("x.foo = 1.0; return x;"),
            "3:2: '.foo' is neither a swizzle nor a member: only structs have members");
  EXPECT_EQ(error("return S;"), "3:8: unexpected type 'S'");
  EXPECT_EQ(error("return 1.0;", "S f(float x)"),
            "2:1: function 'f' returns a struct (S): a reference returns a float (return one "
            "member, or call it from a function that does)");
  EXPECT_EQ(located(shader_error("struct S { float a[2]; };\nfloat f(float x) { S s; return x; }")),
            "1:18: arrays inside structs are not supported (a[])" + kSubsetNote);
  EXPECT_EQ(located(shader_error("struct S { float a; S b; };\nfloat f(float x) { S s; return x; }")),
            "1:8: struct 'S' contains itself");
  EXPECT_EQ(located(shader_error("struct S { Texture2D t; };\nfloat f(float x) { S s; return x; }")),
            "1:12: textures are not supported (Texture2D)" + kSubsetNote);
  EXPECT_EQ(located(shader_error(
                "struct S { float a; float g() { return a; } };\nfloat f(float x) { S s; return x; }")),
            "1:27: functions inside structs are not supported (g)" + kSubsetNote);
  EXPECT_EQ(located(shader_error("struct S { float a; } g;\nfloat f(float x) { return g.a; }")),
            "2:27: global variables are not supported (g)" + kSubsetNote);
  EXPECT_EQ(located(shader_error("float f(float x) { struct T { float a; }; return x; }")),
            "1:20: structs declared inside functions are not supported (struct)" + kSubsetNote);
}

}  // namespace
}  // namespace shaderfit::reference
