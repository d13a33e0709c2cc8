// The shader front end's matrices (language_matrix.cpp and the parser's uses of it): GLSL's
// mat2-mat4 and matCxR (filled by columns, m[i] a column, `*` the product) and HLSL's float3x3
// (filled by rows, m[i] a row, `*` component by component, mul() the product), as locals,
// file-scope constants and helpers' parameters. Checked by values at points against the C++
// they mean, and each bad input by its message and location.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <string>

#include "reference/shader_test_util.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/reference/language.hpp"

namespace shaderfit::reference {
namespace {

using testing::at;
using testing::located;
using testing::shader;
using testing::shader_error;

using Mat3 = std::array<std::array<double, 3>, 3>;  // rows
using Vec3 = std::array<double, 3>;

Vec3 times(const Mat3& m, const Vec3& v) {
  Vec3 r{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r[i] += m[i][j] * v[j];
  return r;
}

// Hill's fit of the ACES transforms, as both languages write it (the same matrices, GLSL's
// listed by columns).
const Mat3 kInput = {{{0.59719, 0.35458, 0.04823}, {0.07600, 0.90834, 0.01566},
                      {0.02840, 0.13383, 0.83777}}};
const Mat3 kOutput = {{{1.60475, -0.53108, -0.07367}, {-0.10208, 1.10813, -0.00605},
                       {-0.00327, -0.07276, 1.07602}}};

double aces_fitted(double x, int channel) {
  Vec3 c = times(kInput, {x, 0.5 * x, 0.25 * x});
  for (double& v : c)
    v = (v * (v + 0.0245786) - 0.000090537) / (v * (0.983729 * v + 0.4329510) + 0.238081);
  return std::clamp(times(kOutput, c)[static_cast<std::size_t>(channel)], 0.0, 1.0);
}

TEST(ShaderMatrices, AcesFittedInHlslWithMul) {
  const std::string source = R"(
static const float3x3 ACESInputMat = {
  {0.59719, 0.35458, 0.04823},
  {0.07600, 0.90834, 0.01566},
  {0.02840, 0.13383, 0.83777}
};
static const float3x3 ACESOutputMat = float3x3(
   1.60475, -0.53108, -0.07367,
  -0.10208,  1.10813, -0.00605,
  -0.00327, -0.07276,  1.07602);
float3 RRTAndODTFit(float3 v) {
  float3 a = v * (v + 0.0245786f) - 0.000090537f;
  float3 b = v * (0.983729f * v + 0.4329510f) + 0.238081f;
  return a / b;
}
float3 ACESFitted(float3 color) {
  color = mul(ACESInputMat, color);
  color = RRTAndODTFit(color);
  color = mul(ACESOutputMat, color);
  return saturate(color);
}
float red(float x) { return ACESFitted(float3(x, 0.5 * x, 0.25 * x)).r; }
float blue(float x) { return ACESFitted(float3(x, 0.5 * x, 0.25 * x)).b; }
)";
  const Program r = shader(source, "red", {}, "aces.hlsl");
  const Program b = shader(source, "blue", {}, "aces.hlsl");
  for (const double x : {0.05, 0.4, 1.5, 6.0}) {
    EXPECT_NEAR(at(r, {x}), aces_fitted(x, 0), 1e-14) << x;
    EXPECT_NEAR(at(b, {x}), aces_fitted(x, 2), 1e-14) << x;
  }
}

TEST(ShaderMatrices, AcesFittedInGlslByColumns) {
  const Program p = shader(R"(
const mat3 ACESInputMat = mat3(
    0.59719, 0.07600, 0.02840,
    0.35458, 0.90834, 0.13383,
    0.04823, 0.01566, 0.83777);
const mat3 ACESOutputMat = mat3(
     1.60475, -0.10208, -0.00327,
    -0.53108,  1.10813, -0.07276,
    -0.07367, -0.00605,  1.07602);
vec3 RRTAndODTFit(vec3 v) {
  vec3 a = v * (v + 0.0245786) - 0.000090537;
  vec3 b = v * (0.983729 * v + 0.4329510) + 0.238081;
  return a / b;
}
float f(float x) {
  vec3 color = ACESInputMat * vec3(x, 0.5 * x, 0.25 * x);
  color = RRTAndODTFit(color);
  color = ACESOutputMat * color;
  return clamp(color, 0.0, 1.0).g;
})");
  for (const double x : {0.05, 0.4, 1.5, 6.0}) EXPECT_NEAR(at(p, {x}), aces_fitted(x, 1), 1e-14);
}

// Subscripts, the row and column sides of a product, transposes, diagonal constructors and the
// component-by-component operators of each language.
TEST(ShaderMatrices, SubscriptsProductsAndConstructors) {
  const Program glsl = shader(R"(
float f(float x) {
  mat2 m = mat2(1.0, 2.0, 3.0, x);   // columns (1, 2) and (3, x)
  vec2 v = vec2(1.0, 10.0);
  vec2 mv = m * v;                   // (1 + 30, 2 + 10 x)
  vec2 vm = v * m;                   // (1 + 20, 3 + 10 x)
  mat2 d = mat2(2.0);                // 2 on the diagonal
  mat2 p = m * d + 1.0;              // every element 2 m + 1
  return mv.x + 100.0 * mv.y + 1e4 * vm.y + 1e6 * m[1][0] + 1e7 * p[0][1] + 1e8 * transpose(m)[0][1];
})");
  const double x = 0.5;
  EXPECT_DOUBLE_EQ(at(glsl, {x}), 31 + 100 * (2 + 10 * x) + 1e4 * (3 + 10 * x) + 1e6 * 3 + 1e7 * 5 + 1e8 * 3);

  const Program hlsl = shader(R"(
float f(float x) {
  float2x2 m = float2x2(1.0, 2.0, 3.0, x);   // rows (1, 2) and (3, x)
  float2 v = float2(1.0, 10.0);
  float2 mv = mul(m, v);                      // (21, 3 + 10 x)
  float2 vm = mul(v, m);                      // (31, 2 + 10 x)
  float2x2 e = m * m;                         // component by component
  float2x3 w = { 1, 2, 3, 4, 5, 6 };
  float3 wv = mul(float2(1, 1), w);           // (5, 7, 9)
  return mv.y + 100.0 * vm.y + 1e4 * e[1][1] + 1e5 * m[1].x + 1e6 * wv.z + 1e7 * mul(v, v);
})",
                              "f", {}, "test.hlsl");
  EXPECT_DOUBLE_EQ(at(hlsl, {x}),
                   3 + 10 * x + 100 * (2 + 10 * x) + 1e4 * x * x + 1e5 * 3 + 1e6 * 9 + 1e7 * 101);
}

TEST(ShaderMatrices, BadInputIsOneClearError) {
  auto error = [](const std::string& body) {
    return located(shader_error("float f(float x) {\n" + body + "\n}\n"));
  };
  EXPECT_EQ(error("mat2 m = mat2(1.0, 2.0, 3.0); return x;"),
            "2:10: mat2(...) is given 3 components, and has 4");
  EXPECT_EQ(error("mat2 m = mat2(x); vec3 v = vec3(x); return (m * v).x;"),
            "2:47: '*' of a mat2 and a float3: their sizes do not fit");
  EXPECT_EQ(error("float2x2 m = (float2x2)x; return (m * float2(x, x)).x;"),
            "2:37: '*' of a float2x2 and a float2 (mul() is the product)");
  EXPECT_EQ(error("float2x2 m = (float2x2)x; return m < m;"),
            "2:36: '<' of matrices is not supported");
  EXPECT_EQ(error("float2x2 m = (float2x2)x; return sqrt(m);"),
            "2:34: sqrt of a float2x2: a matrix is not a number (use m[i][j])");
  EXPECT_EQ(error("float2x2 m = (float2x2)x; return m;"),
            "2:27: cannot give a float2x2 to the result of f, a float");
  EXPECT_EQ(error("float2x2 m = (float2x2)x; m[0][1] = 2.0; return x;"),
            "2:28: writing part of a float2x2 is not supported: a matrix is assigned whole");
  EXPECT_EQ(error("float2x2 m = (float2x2)x; return m[2][0];"),
            "2:35: a subscript of a float2x2 must be a constant from 0 to 1");
  EXPECT_EQ(error("float2x2 m = (float2x2)x; return m._m00;"),
            "2:35: a member of a float2x2: a matrix's elements are read as m[i][j]");
  EXPECT_EQ(error("float3 v = float3(x, x, x); return mul(v, float2(x, x));"),
            "2:36: mul of a float3 and a float2: their sizes do not fit");
  EXPECT_EQ(error("int3x3 m; return x;"),
            "2:1: matrix types are not supported (int3x3)" + testing::kSubsetNote);
}

}  // namespace
}  // namespace shaderfit::reference
