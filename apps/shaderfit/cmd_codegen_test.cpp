#include <fmt/format.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <iostream>

#include "cli_test_util.hpp"
#include "codegen/toolchain_test_support.hpp"

namespace shaderfit::cli::testing {
namespace {

TEST(CmdCodegen, PrintsOneFunction) {
  const CliResult r = run({"codegen", "--lang", "cuda", "--name", "fresnel",
                           "r0 + (1 - cos_theta - r0) * (1 - cos_theta)^4"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("__device__ __forceinline__ float fresnel(float r0, float cos_theta) {"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("fmaf("), std::string::npos) << r.out;
}

// The comment above the code shows the formula for people: float32's shortest constants, and
// one sign in a sum.
TEST(CmdCodegen, CommentShowsShortConstants) {
  const CliResult r = run({"codegen", "--lang", "glsl", "x * 0.5829255932120166 - -0.25"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("// 0.5829256 * x + 0.25\n"), std::string::npos) << r.out;
}

TEST(CmdCodegen, InputsAndParamsKeepTheirNamesAndOrder) {
  const CliResult r = run({"codegen", "--lang", "glsl", "--inputs", "cos_theta,r0", "--params", "s",
                           "r0 + (1 - r0 - s * cos_theta) * (1 - cos_theta)^4"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("float shaderfit_formula(float cos_theta, float r0, float s) {"),
            std::string::npos)
      << r.out;
}

TEST(CmdCodegen, WholeFront) {
  const std::string path = scratch_file("front.json", R"({"inputs": ["r0", "cos_theta"], "front": [
    {"formula": "r0 + (1 - r0) * (1 - cos_theta)^5"},
    {"formula": "r0 + (1 - r0 - s * cos_theta) * (1 - cos_theta)^4", "parameters": {"s": 0.25}}]})");
  const CliResult r = run({"codegen", "--lang", "hlsl", "--name", "f", "--front", path});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("float f_0(float r0, float cos_theta) {"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("float f_1(float r0, float cos_theta) {"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("const float s = 0.25f;"), std::string::npos) << r.out;
}

// A front whose members use every spelling the printer has (fma, the calls, saturate, rsqrt,
// sign, copysign, select, a baked parameter).
std::string every_spelling_front() {
  return scratch_file("every_spelling.json", R"json({"inputs": ["r0", "cos_theta", "x"], "front": [
    {"formula": "r0 + (1 - cos_theta - r0) * (1 - cos_theta)^4"},
    {"formula": "saturate(rsqrt(x)) + exp(-x) * log2(x) - 1 / cos_theta"},
    {"formula": "select(x >= r0, sign(x), copysign(r0, x)) + copysign(2, r0) * select(-x >= 0, r0, 2)"},
    {"formula": "min(x, r0) * max(sin(x), cos(r0)) + abs(x) + sqrt(exp2(x)) + log(r0)"},
    {"formula": "r0 + (1 - r0 - s * cos_theta) * (1 - cos_theta)^4", "parameters": {"s": 0.25}}]})json");
}

struct Printed {
  std::string lang, text;
};

// `shaderfit codegen --lang L` of the README's formula and of the front above, as printed.
std::vector<Printed> printed(const std::string& lang) {
  std::vector<Printed> out;
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"codegen", "--lang", lang, "--name", "fresnel",
                                 "r0 + (1 - cos_theta - r0) * (1 - cos_theta)^4"},
        std::vector<std::string>{"codegen", "--lang", lang, "--front", every_spelling_front()}}) {
    const CliResult r = run(args);
    EXPECT_EQ(r.status, 0) << r.err;
    out.push_back({lang, r.out});
  }
  return out;
}

// Compiles `text` as file `name` in a scratch folder with `command` ({} is the file); the
// compiler's messages and the text on failure.
void expect_compiles(const std::string& text, const std::string& name, const std::string& command) {
  const auto dir = shaderfit::testing::scratch_folder("codegen_as_printed");
  shaderfit::testing::write_text(dir / name, text);
  std::string log;
  const int status = shaderfit::testing::run_command(
      "cd '" + dir.string() + "' && " + fmt::format(fmt::runtime(command), name), &log);
  EXPECT_EQ(status, 0) << command << ":\n" << log << "\n" << text;
}

TEST(CmdCodegen, CppCompilesAsPrinted) {
  bool any = false;
  for (const char* tool : {"g++", "clang++"}) {
    const auto cxx = shaderfit::testing::find_tool(tool);
    if (!cxx) continue;
    any = true;
    for (const Printed& p : printed("cpp"))
      expect_compiles(p.text, "printed.cpp",
                      "'" + *cxx + "' -std=c++17 -Wall -pedantic -Werror -c {} -o printed.o");
  }
  if (!any) GTEST_SKIP() << "skipped: g++ and clang++ not found";
  // Only what is used is included: a product needs no header.
  EXPECT_EQ(run({"codegen", "--lang", "cpp", "x * y"}).out.find("#include"), std::string::npos);
}

TEST(CmdCodegen, CudaCompilesAsPrinted) {
  const auto nvcc = shaderfit::testing::find_tool("nvcc");
  if (!nvcc) GTEST_SKIP() << "skipped: nvcc not found";
  // The front alone: one nvcc call (seconds), and it holds every spelling.
  expect_compiles(printed("cuda").back().text, "printed.cu", "'" + *nvcc + "' -c {} -o printed.o");
}

// GLSL and HLSL with the entry point a shader stage requires appended, nothing else.
TEST(CmdCodegen, GlslAndHlslCompileAsPrinted) {
  const auto glslang = shaderfit::testing::find_tool("glslangValidator");
  const auto dxc = shaderfit::testing::find_tool("dxc");
  if (!glslang && !dxc) GTEST_SKIP() << "skipped: glslangValidator and dxc not found";
  if (glslang) {
    for (const Printed& p : printed("glsl")) {
      EXPECT_EQ(p.text.rfind("#version 450\n", 0), 0u) << p.text;
      expect_compiles(p.text + "void main() {}\n", "printed.frag",
                      "'" + *glslang + "' -V {} -o printed.spv");
    }
  }
  for (const Printed& p : printed("hlsl")) {
    const std::string text = p.text + "float4 main() : SV_Target { return float4(0, 0, 0, 0); }\n";
    if (glslang)
      expect_compiles(text, "printed.hlsl",
                      "'" + *glslang + "' -D -V -S frag -e main {} -o printed.spv");
    if (dxc) expect_compiles(text, "printed.hlsl", "'" + *dxc + "' -T ps_6_0 -E main {}");
  }
  if (!dxc) std::cout << "skipped: dxc not found (HLSL checked with glslangValidator)\n";
}

TEST(CmdCodegen, UnknownLanguage) {
  const CliResult r = run({"codegen", "--lang", "fortran", "a + b"});
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(line_count(r.err), 1);
  EXPECT_NE(r.err.find("unknown language 'fortran'"), std::string::npos) << r.err;
}

// --precision half: the half form of each language (docs/precision.md, "Half code").
TEST(CmdCodegen, HalfPrecision) {
  const CliResult r = run({"codegen", "--lang", "cuda", "--precision", "half", "--name", "fresnel",
                           "r0 + (x - r0) * x^4"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out.rfind("#include <cuda_fp16.h>\n", 0), 0u) << r.out;
  EXPECT_NE(r.out.find("// cost model: 5 SASS per __half2 (2.5 per value)\n"), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("__host__ __device__ __forceinline__ __half fresnel(__half r0, __half x)"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("__device__ __forceinline__ __half2 fresnel_x2(__half2 r0, __half2 x)"),
            std::string::npos)
      << r.out;
  const CliResult glsl = run({"codegen", "--lang", "glsl", "--precision", "half", "x * 0.1"});
  ASSERT_EQ(glsl.status, 0) << glsl.err;
  EXPECT_NE(glsl.out.find("float16_t shaderfit_formula(float16_t x) {\n  return x * 0.1hf;"),
            std::string::npos)
      << glsl.out;
}

TEST(CmdCodegen, BadPrecision) {
  expect_bad_input({"codegen", "--lang", "glsl", "--precision", "quarter", "x"},
                   "--precision: unknown precision 'quarter'");
  expect_bad_input({"codegen", "--lang", "glsl", "--precision", "double", "x"},
                   "--precision: code generation has no double form");
  expect_bad_input({"codegen", "--lang", "cpp", "--precision", "half", "x"},
                   "C++ has no half type");
  expect_bad_input({"codegen", "--lang", "glsl", "--precision", "half", "sign(x)"},
                   "sign has no half form");
}

TEST(CmdCodegen, BadFormula) {
  const CliResult r = run({"codegen", "--lang", "glsl", "a + (b"});
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(line_count(r.err), 1);
  EXPECT_NE(r.err.find("formula:1:"), std::string::npos) << r.err;
}

TEST(CmdCodegen, MissingFrontFile) {
  const CliResult r = run({"codegen", "--lang", "glsl", "--front", "/nonexistent/front.json"});
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(line_count(r.err), 1);
  EXPECT_NE(r.err.find("/nonexistent/front.json"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace shaderfit::cli::testing
