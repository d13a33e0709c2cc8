#include "shaderfit/codegen/codegen.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>

#include "shaderfit/core/error.hpp"
#include "shaderfit/core/random.hpp"
#include "shaderfit/expr/parse.hpp"

namespace shaderfit {
namespace {

std::string gen(const std::string& f, Language l, std::vector<std::string> params = {}) {
  ParseOptions po;
  po.parameters = std::move(params);
  CodegenOptions o;
  o.language = l;
  o.name = "f";
  return generate_function(parse_formula(f, po), o);
}

TEST(Codegen, Float32LiteralsRoundTrip) {
  Rng rng(5);
  for (int i = 0; i < 10000; ++i) {
    std::uint32_t bits = static_cast<std::uint32_t>(rng());
    float v;
    std::memcpy(&v, &bits, 4);
    if (!std::isfinite(v)) continue;
    for (Language l : {Language::Glsl, Language::Cuda}) {
      const std::string t = float32_literal(v, l);
      EXPECT_EQ(std::strtof(t.c_str(), nullptr), v) << t;
      EXPECT_NE(t.find_first_of(".e"), std::string::npos) << t;
      EXPECT_EQ(t.back() == 'f', l == Language::Cuda) << t;
    }
  }
  EXPECT_EQ(float32_literal(1.0, Language::Glsl), "1.0");
  EXPECT_EQ(float32_literal(0.1, Language::Cpp), "0.1f");
  EXPECT_THROW(float32_literal(1e300, Language::Cpp), Error);
}

TEST(Codegen, SeedFormulaInEveryLanguage) {
  const std::string f = "r0 + (1 - cos_theta - r0) * (1 - cos_theta)^4";
  EXPECT_EQ(gen(f, Language::Cuda),
            "__device__ __forceinline__ float f(float r0, float cos_theta) {\n"
            "  const float t0 = 1.0f - cos_theta;\n"
            "  const float t1 = t0 * t0;\n"
            "  return fmaf(t0 - r0, t1 * t1, r0);\n}\n");
  EXPECT_EQ(gen(f, Language::Glsl),
            "float f(float r0, float cos_theta) {\n"
            "  float t0 = 1.0 - cos_theta;\n"
            "  float t1 = t0 * t0;\n"
            "  return r0 + (t0 - r0) * (t1 * t1);\n}\n");
  EXPECT_NE(gen(f, Language::Cpp).find("std::fma(t0 - r0, t1 * t1, r0)"), std::string::npos);
  EXPECT_NE(gen(f, Language::Metal).find("inline float f(float r0, float cos_theta)"), std::string::npos);
  EXPECT_NE(gen(f, Language::Hlsl).find("float t0 = 1.0f - cos_theta;"), std::string::npos);
}

TEST(Codegen, FunctionsPerLanguage) {
  EXPECT_NE(gen("saturate(rsqrt(x))", Language::Glsl).find("clamp(inversesqrt(x), 0.0, 1.0)"), std::string::npos);
  EXPECT_NE(gen("saturate(rsqrt(x))", Language::Hlsl).find("saturate(rsqrt(x))"), std::string::npos);
  EXPECT_NE(gen("saturate(rsqrt(x))", Language::Cuda).find("__saturatef(rsqrtf(x))"), std::string::npos);
  EXPECT_NE(gen("saturate(rsqrt(x))", Language::Cpp).find("std::clamp(1.0f / std::sqrt(x), 0.0f, 1.0f)"), std::string::npos);
  EXPECT_NE(gen("x - 1 / y", Language::Cuda).find("x + -1.0f / y"), std::string::npos);
}

TEST(Codegen, SignCopysignSelectPerLanguage) {
  const std::string f = "select(x >= y, sign(x), copysign(y, x)) + copysign(2, y)";
  const std::string glsl = gen(f, Language::Glsl);
  EXPECT_NE(glsl.find("uintBitsToFloat((floatBitsToUint(y) & 0x7fffffffu) | (floatBitsToUint(x) & "
                      "0x80000000u))"),
            std::string::npos)
      << glsl;
  EXPECT_NE(glsl.find("uintBitsToFloat(0x40000000u | (floatBitsToUint(y) & 0x80000000u))"),
            std::string::npos)
      << glsl;
  EXPECT_NE(glsl.find("x < 0.0 ? -1.0 : x"), std::string::npos) << glsl;
  EXPECT_NE(glsl.find("x >= y ? "), std::string::npos) << glsl;  // a compared difference
  const std::string hlsl = gen(f, Language::Hlsl);
  EXPECT_NE(hlsl.find("asfloat((asuint(y) & 0x7fffffffu) | (asuint(x) & 0x80000000u))"),
            std::string::npos)
      << hlsl;
  const std::string cuda = gen(f, Language::Cuda);
  EXPECT_NE(cuda.find("fabsf(x) > 0.0f ? copysignf(1.0f, x) : x"), std::string::npos) << cuda;
  EXPECT_NE(cuda.find("copysignf(y, x)"), std::string::npos) << cuda;
  const std::string cpp = gen(f, Language::Cpp);
  EXPECT_NE(cpp.find("std::copysign(2.0f, y)"), std::string::npos) << cpp;
  // A negated condition is written a <= 0.
  EXPECT_NE(gen("select(-x >= 0, y, 2)", Language::Metal).find("x <= 0.0f ? y : 2.0f"),
            std::string::npos);
}

std::string source(const std::vector<std::string>& formulas, Language l) {
  std::vector<SourceFunction> fs;
  for (std::size_t i = 0; i < formulas.size(); ++i) {
    SourceFunction f{parse_formula(formulas[i]), {}};
    f.options.name = "f" + std::to_string(i);
    fs.push_back(std::move(f));
  }
  return generate_source(fs, l);
}

TEST(Codegen, LibraryFunctionsPerLanguage) {
  const std::string f = "asin(x) + acos(y) * atan(x) - atan2(y, x) + tanh(x)";
  const std::string glsl = gen(f, Language::Glsl);
  for (const char* call : {"asin(x)", "acos(y)", "atan(x)", "atan(y, x)", "tanh(x)"})
    EXPECT_NE(glsl.find(call), std::string::npos) << call << "\n" << glsl;
  EXPECT_NE(gen(f, Language::Hlsl).find("atan2(y, x)"), std::string::npos);
  EXPECT_NE(gen(f, Language::Metal).find("atan2(y, x)"), std::string::npos);
  const std::string cuda = gen(f, Language::Cuda);
  for (const char* call : {"asinf(x)", "acosf(y)", "atanf(x)", "atan2f(y, x)", "tanhf(x)"})
    EXPECT_NE(cuda.find(call), std::string::npos) << call << "\n" << cuda;
  const std::string cpp = gen(f, Language::Cpp);
  for (const char* call :
       {"std::asin(x)", "std::acos(y)", "std::atan(x)", "std::atan2(y, x)", "std::tanh(x)"})
    EXPECT_NE(cpp.find(call), std::string::npos) << call << "\n" << cpp;
  // erf: the library's in CUDA and C++; elsewhere the helper, written before the function.
  EXPECT_NE(gen("erf(x)", Language::Cuda).find("return erff(x);"), std::string::npos);
  EXPECT_NE(gen("erf(x)", Language::Cpp).find("return std::erf(x);"), std::string::npos);
  for (Language l : {Language::Glsl, Language::Hlsl, Language::Metal}) {
    const std::string t = gen("erf(x) * 2", l);
    const std::size_t helper = t.find("float sf_erf(float x) {");
    ASSERT_NE(helper, std::string::npos) << t;
    EXPECT_LT(helper, t.find("float f(float x) {")) << t;
    EXPECT_NE(t.find("sf_erf(x) * 2.0"), std::string::npos) << t;
  }
  EXPECT_EQ(gen("erf(x) * 2", Language::Cuda).find("sf_erf"), std::string::npos);
  // A source defines the helper once, however many functions call it, and not when none does.
  const std::string two = source({"erf(x)", "erf(x * 2) + x", "x"}, Language::Glsl);
  EXPECT_EQ(two.find("float sf_erf(float x) {"), two.rfind("float sf_erf(float x) {"));
  EXPECT_EQ(two.rfind("#version 450\n\n// erf(x):", 0), 0u) << two;
  EXPECT_EQ(source({"tanh(x)"}, Language::Hlsl).find("sf_erf"), std::string::npos);
  // The C++ source includes <cmath> for them.
  EXPECT_EQ(source({"atan2(x, y)"}, Language::Cpp).rfind("#include <cmath>\n", 0), 0u);
  // The names they call are reserved.
  EXPECT_THROW(gen("erf(sf_erf)", Language::Glsl), Error);
  EXPECT_THROW(gen("atan2f + 1", Language::Cuda), Error);
}

TEST(Codegen, ParametersAsArgumentsOrBaked) {
  ParseOptions po;
  po.parameters = {"s"};
  po.parameter_values = {0.25};
  const Expression e = parse_formula("x * s", po);
  CodegenOptions o;
  o.language = Language::Cpp;
  o.name = "g";
  EXPECT_NE(generate_function(e, o).find("inline float g(float x, float s)"), std::string::npos);
  o.bake_parameters = true;
  EXPECT_NE(generate_function(e, o).find("const float s = 0.25f;"), std::string::npos);
}

TEST(Codegen, SourceHasWhatItsFunctionsNeed) {
  // C++: the headers of what the functions call, and only those.
  EXPECT_EQ(
      source({"(x + y) / (x - y)"}, Language::Cpp).rfind("inline float f0(float x, float y) {", 0),
      0u);
  EXPECT_EQ(source({"x * y + 1"}, Language::Cpp)  // std::fma
                .rfind("#include <cmath>\n\ninline float f0(float x, float y) {", 0),
            0u);
  EXPECT_EQ(source({"saturate(x)"}, Language::Cpp).rfind("#include <algorithm>\n\ninline", 0), 0u);
  EXPECT_EQ(source({"sign(x)", "saturate(x)"}, Language::Cpp)
                .rfind("#include <algorithm>\n#include <cmath>\n\ninline float f0(", 0),
            0u);
  // GLSL: the #version line glslangValidator needs; Metal: its header; CUDA, HLSL: nothing.
  const std::string glsl = source({"x + 1", "x * y"}, Language::Glsl);
  EXPECT_EQ(glsl,
            "#version 450\n\nfloat f0(float x) {\n  return x + 1.0;\n}\n\n"
            "float f1(float x, float y) {\n  return x * y;\n}\n");
  EXPECT_EQ(source({"x"}, Language::Metal)
                .rfind("#include <metal_stdlib>\nusing namespace metal;\n\n", 0),
            0u);
  for (Language l : {Language::Cuda, Language::Hlsl})
    EXPECT_EQ(source({"sqrt(x)"}, l).rfind(l == Language::Cuda ? "__device__" : "float f0", 0), 0u);
  // The functions keep the names and checks of generate_function.
  EXPECT_THROW(source({"in + 1"}, Language::Cpp), Error);
}

TEST(Codegen, BadNamesAreErrors) {
  EXPECT_THROW(gen("in + 1", Language::Glsl), Error);   // reserved
  EXPECT_THROW(gen("copysignf + 1", Language::Cuda), Error);        // called by copysign
  EXPECT_THROW(gen("floatBitsToUint * 2", Language::Glsl), Error);  // and by its GLSL form
  CodegenOptions o;
  o.name = "2f";
  EXPECT_THROW(generate_function(parse_formula("x"), o), Error);
}

}  // namespace
}  // namespace shaderfit
