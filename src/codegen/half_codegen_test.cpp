// Half code generation (CodegenOptions::precision = Half): the text per language, the literals,
// and what has no half form. The compilers' view of the same text is
// half_compiler_check_test.cpp.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "shaderfit/codegen/codegen.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/expr/precision.hpp"

namespace shaderfit {
namespace {

CodegenOptions half_options(Language l, const std::string& name = "f") {
  CodegenOptions o;
  o.language = l;
  o.name = name;
  o.precision = Precision::Half;
  return o;
}

std::string half(const std::string& formula, Language l) {
  return generate_function(parse_formula(formula), half_options(l));
}

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// The literal's number reads back to the binary16 value directly and through float32.
double literal_value(const std::string& literal) {
  const std::size_t start = literal.find_first_of("-0123456789");
  return std::strtod(literal.c_str() + start, nullptr);
}

TEST(HalfCodegen, LiteralsAreTheShortestTextOfTheHalfValue) {
  EXPECT_EQ(half_literal(0.1, Language::Glsl), "0.1hf");  // binary16 0.0999755859375
  EXPECT_EQ(half_literal(1.0, Language::Hlsl), "1.0h");
  EXPECT_EQ(half_literal(-5.55473, Language::Metal), "-5.555h");  // -5.5546875
  EXPECT_EQ(half_literal(0.5, Language::Cuda), "__float2half(0.5f)");
  EXPECT_EQ(half_literal(65504.0, Language::Glsl), "6.55e+04hf");
  EXPECT_EQ(half_literal(1e-8, Language::Glsl), "0.0hf");  // below half the smallest subnormal
  for (double v : {0.1, 0.3, 1.0 / 3.0, 3.14159265, 6.98316, 1e-5, 6e-8, 1000.7, 65504.0}) {
    const double h = round_to_half(v);
    const std::string t = half_literal(v, Language::Glsl);
    EXPECT_EQ(round_to_half(literal_value(t)), h) << t;
    EXPECT_EQ(round_to_half(static_cast<double>(std::strtof(t.c_str(), nullptr))), h) << t;
  }
  EXPECT_THROW(half_literal(65520.0, Language::Glsl), Error);  // rounds to infinity
  EXPECT_THROW(half_literal(0.5, Language::Cpp), Error);
}

TEST(HalfCodegen, SeedFormulaInEachLanguage) {
  const std::string f = "r0 + (x - r0) * x^4";
  EXPECT_EQ(half(f, Language::Glsl),
            "// needs #extension GL_EXT_shader_explicit_arithmetic_types_float16 : require\n"
            "float16_t f(float16_t r0, float16_t x) {\n"
            "  float16_t t0 = x * x;\n"
            "  return r0 + (x - r0) * (t0 * t0);\n}\n");
  EXPECT_EQ(half(f, Language::Hlsl),
            "// half needs 16-bit types: dxc -enable-16bit-types (glslangValidator "
            "--hlsl-enable-16bit-types)\n"
            "half f(half r0, half x) {\n"
            "  half t0 = x * x;\n"
            "  return r0 + (x - r0) * (t0 * t0);\n}\n");
  EXPECT_EQ(half(f, Language::Metal),
            "inline half f(half r0, half x) {\n"
            "  const half t0 = x * x;\n"
            "  return r0 + (x - r0) * (t0 * t0);\n}\n");
  // CUDA: the _rn intrinsics (never contracted into an fma), the __half form for host and device
  // and the __half2 twin.
  EXPECT_EQ(half(f, Language::Cuda),
            "// needs #include <cuda_fp16.h>\n"
            "__host__ __device__ __forceinline__ __half f(__half r0, __half x) {\n"
            "  const __half t0 = __hmul_rn(x, x);\n"
            "  return __hadd_rn(r0, __hmul_rn(__hsub_rn(x, r0), __hmul_rn(t0, t0)));\n}\n"
            "__device__ __forceinline__ __half2 f_x2(__half2 r0, __half2 x) {\n"
            "  const __half2 t0 = __hmul2_rn(x, x);\n"
            "  return __hadd2_rn(r0, __hmul2_rn(__hsub2_rn(x, r0), __hmul2_rn(t0, t0)));\n}\n");
}

TEST(HalfCodegen, PowersFollowTheSquaringChainAndFmaOnlyWhereWritten) {
  // x^5 = x^4 * x by apply_ipow's chain; a * b + c stays a product and a sum.
  const std::string s = half("r0 + (1 - r0) * (1 - x)^5", Language::Glsl);
  EXPECT_TRUE(has(s, "float16_t t0 = 1.0hf - x;")) << s;
  EXPECT_TRUE(has(s, "float16_t t1 = t0 * t0;")) << s;
  EXPECT_TRUE(has(s, "return r0 + (1.0hf - r0) * (t0 * (t1 * t1));")) << s;
  EXPECT_FALSE(has(half("a * b + c", Language::Cuda), "fma")) << half("a * b + c", Language::Cuda);
  EXPECT_TRUE(has(half("fma(a, b, c)", Language::Glsl), "fma(a, b, c)"));
  EXPECT_TRUE(has(half("fma(a, b, c)", Language::Hlsl), "(half)mad(a, b, c)"));
  const std::string cuda = half("fma(a, b, c)", Language::Cuda);
  EXPECT_TRUE(has(cuda, "sf_hfma(a, b, c)")) << cuda;
  EXPECT_TRUE(has(cuda, "__hfma2(a, b, c)")) << cuda;
  // A division is one (one rounding); by a power of two it is the exact product.
  EXPECT_TRUE(has(half("x / y", Language::Glsl), "return x / y;"));
  EXPECT_TRUE(has(half("x / 4", Language::Glsl), "return x * 0.25hf;"));
  EXPECT_TRUE(has(half("x / 3", Language::Glsl), "return x / 3.0hf;"));
  // 1 / sqrt(x) rounds twice, as written; rsqrt(x) once.
  EXPECT_TRUE(has(half("1 / sqrt(x)", Language::Glsl), "1.0hf / sqrt(x)"));
  EXPECT_TRUE(has(half("rsqrt(x)", Language::Glsl), "inversesqrt(x)"));
}

TEST(HalfCodegen, ConstantsFoldInHalf) {
  // 0.1 * 3 folds as evaluate_half computes it: binary16 0.1 times 3, rounded to binary16.
  const double folded = round_to_half(round_to_half(0.1) * 3.0);
  const std::string s = half("x * (0.1 * 3)", Language::Glsl);
  EXPECT_TRUE(has(s, "x * " + half_literal(folded, Language::Glsl))) << s;
  EXPECT_THROW(half("x * 70000", Language::Glsl), Error);
}

TEST(HalfCodegen, FunctionsPerLanguage) {
  const std::string f =
      "exp2(x) + log2(x) + sqrt(x) + rsqrt(x) + 1 / x + exp(x) + log(x) + "
      "sin(x) + cos(x) + abs(x) * min(x, y) - max(x, y) + saturate(y)";
  const std::string glsl = half(f, Language::Glsl);
  for (const char* s :
       {"exp2(x)", "log2(x)", "sqrt(x)", "inversesqrt(x)", "1.0hf / x", "exp(x)", "log(x)",
        "sin(x)", "cos(x)", "abs(x)", "min(x, y)", "max(x, y)", "clamp(y, 0.0hf, 1.0hf)"})
    EXPECT_TRUE(has(glsl, s)) << s << "\n" << glsl;
  // glslang's HLSL reads half arguments of intrinsics as float: the results are cast back.
  const std::string hlsl = half(f, Language::Hlsl);
  for (const char* s : {"(half)exp2(x)", "(half)rsqrt(x)", "(half)saturate(y)", "(half)min(x, y)"})
    EXPECT_TRUE(has(hlsl, s)) << s << "\n" << hlsl;
  const std::string metal = half(f, Language::Metal);
  for (const char* s : {"rsqrt(x)", "fabs(x)", "fmin(x, y)", "saturate(y)", "1.0h / x"})
    EXPECT_TRUE(has(metal, s)) << s << "\n" << metal;
  const std::string cuda = half(f, Language::Cuda);
  for (const char* s :
       {"sf_hexp2(x)", "sf_hrsqrt(x)", "sf_hrcp(x)", "__habs(x)", "__hmin(x, y)",
        "__hadd_sat(y, __float2half(0.0f))", "h2exp2(x)", "h2rsqrt(x)", "h2rcp(x)", "h2log(x)",
        "sf_h2sin(x)", "__hmax2(x, y)", "__hadd2_sat(y, __float2half2_rn(0.0f))",
        // the helpers: cuda_fp16.h's function on the device, float on the host
        "#ifdef __CUDA_ARCH__\n  return hexp2(x);\n#else\n"
        "  return __float2half(exp2f(__half2float(x)));\n#endif",
        "__floats2half2_rn(__sinf(__low2float(x)), __sinf(__high2float(x)))"})
    EXPECT_TRUE(has(cuda, s)) << s << "\n" << cuda;
  // -1 / x is 1 / -x (rcp is odd): the negation is free in the conversion to float.
  EXPECT_TRUE(has(half("exp2(-1 / x)", Language::Cuda), "h2exp2(h2rcp(__hneg2(x)))"))
      << half("exp2(-1 / x)", Language::Cuda);
}

TEST(HalfCodegen, SourceFileHasTheLinesItsFunctionsNeed) {
  std::vector<SourceFunction> fs = {{parse_formula("exp2(x) * y"), half_options(Language::Glsl)},
                                    {parse_formula("x + y"), half_options(Language::Glsl, "g")}};
  const std::string glsl = generate_source(fs, Language::Glsl);
  EXPECT_EQ(glsl.rfind("#version 450\n#extension GL_EXT_shader_explicit_arithmetic_types_float16 "
                       ": require\n\n",
                       0),
            0u)
      << glsl;
  EXPECT_FALSE(has(glsl, "// needs")) << glsl;
  const std::string cuda = generate_source(fs, Language::Cuda);
  EXPECT_EQ(cuda.rfind("#include <cuda_fp16.h>\n\n// cuda_fp16.h has", 0), 0u) << cuda;
  EXPECT_EQ(cuda.find("sf_hexp2(__half x)"), cuda.rfind("sf_hexp2(__half x)")) << cuda;  // once
  EXPECT_TRUE(has(cuda, "__half2 g_x2(__half2 x, __half2 y)")) << cuda;
  const std::string hlsl = generate_source(fs, Language::Hlsl);
  EXPECT_EQ(hlsl.rfind("// half needs 16-bit types", 0), 0u) << hlsl;
  // Float and half functions in one file.
  fs[1].options.precision = Precision::Float;
  EXPECT_TRUE(has(generate_source(fs, Language::Glsl), "float g(float x, float y)"));
}

TEST(HalfCodegen, ParametersBakeAsHalfConstants) {
  ParseOptions po;
  po.parameters = {"s"};
  Expression e = parse_formula("r0 + (x - r0) * s", po);
  e.parameter_values = {0.1};
  CodegenOptions o = half_options(Language::Cuda);
  o.bake_parameters = true;
  const std::string s = generate_function(e, o);
  EXPECT_TRUE(has(s, "  const __half s = __float2half(0.1f);\n")) << s;
  EXPECT_TRUE(has(s, "  const __half2 s = __float2half2_rn(0.1f);\n")) << s;
}

TEST(HalfCodegen, WhatHasNoHalfFormIsAnError) {
  const auto where = [](const std::string& formula, CodegenOptions o) {
    try {
      (void)generate_function(parse_formula(formula), o);
    } catch (const Error& e) {
      return e.where().source + ": " + e.message();
    }
    return std::string("no error");
  };
  EXPECT_NE(where("x + 1", half_options(Language::Cpp)).find("CodegenOptions::precision: C++"),
            std::string::npos);
  CodegenOptions d = half_options(Language::Glsl);
  d.precision = Precision::Double;
  EXPECT_NE(where("x + 1", d).find("CodegenOptions::precision: code generation has no double"),
            std::string::npos);
  CodegenOptions u = half_options(Language::Glsl);
  u.uniform = {"a"};
  EXPECT_NE(where("a * x", u).find("CodegenOptions::uniform: per-material inputs"),
            std::string::npos);
  for (const char* f : {"sign(x)", "copysign(x, y)", "select(x >= 0, x, y)", "asin(x)", "erf(x)"})
    EXPECT_NE(where(f, half_options(Language::Glsl)).find("formula: "), std::string::npos) << f;
  EXPECT_NE(where("erf(x)", half_options(Language::Metal)).find("erf has no half form"),
            std::string::npos);
  // The __half2 twin's name is taken.
  CodegenOptions c = half_options(Language::Cuda);
  EXPECT_THROW((void)generate_function(parse_formula("f_x2 + 1"), c), Error);
  EXPECT_THROW((void)generate_function(parse_formula("sf_hexp2 + 1"), c), Error);
}

TEST(HalfCodegen, CostCommentNamesTheHalf2Count) {
  EXPECT_EQ(cost_comment(parse_formula("r0 + (x - r0) * x^4"), {}, Precision::Half),
            "cost model: 5 SASS per __half2 (2.5 per value)");
  EXPECT_EQ(cost_comment(parse_formula("r0 + (x - r0) * x^4")),
            "cost model: 4 SASS, 4 PTX, 5 generic, 4 RDNA instructions");
}

}  // namespace
}  // namespace shaderfit
