// Half code against the real compilers (docs/precision.md): nvcc's SASS of the __half2 functions
// against the `sass-half2` target, glslangValidator on the GLSL and HLSL half text, and the CUDA
// __half function run on the CPU through cuda_fp16.h's host arithmetic against evaluate_half.
// Each check skips with "skipped: TOOL not found" where its tool is missing; the model's counts
// are also locked in a test that needs no tool.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <iostream>
#include <sstream>

#include "codegen/compiler_harness_test_support.hpp"
#include "shaderfit/codegen/codegen.hpp"
#include "shaderfit/cost/instruction_model.hpp"
#include "shaderfit/eval/evaluate_in.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/image/half.hpp"

namespace shaderfit {
namespace {

// Formulas with the `sass-half2` count (per __half2 call) that nvcc 13.0 gave for their
// __half2 functions (--use_fast_math -arch=sm_90).
struct HalfFormula {
  const char* text;
  int half2;
};
const HalfFormula kFormulas[] = {
    {"r0 + (1 - r0) * (1 - x)^5", 7},                            // Schlick
    {"r0 + (x - r0) * x^4", 5},                                  // the seed's formula
    {"r0 + (1 - r0 - 0.25 * x) * (1 - x)^4", 8},                 // its shape form
    {"r0 + (1 - r0) * exp2((-5.55473 * x - 6.98316) * x)", 13},  // exp2 forms
    {"exp2(a * x * x + b * x) * c", 12},
    {"2 * x / (x + sqrt(a + (1 - a) * x^2))", 33},     // Smith G1: __h2div
    {"a / (3.14159265 * (x^2 * (a - 1) + 1)^2)", 28},  // GGX D
    {"x / (1 + x)", 23},
    {"rsqrt(x + y) * x", 7},
    {"log2(x) * y", 10},
    {"exp2(log2(c) * 0.45454545)", 17},
    {"min(max(x, y), x * y)", 3},
    {"min(min(x, y), 0.5)", 1},  // one VHMNMX
    {"saturate(x * y)", 2},
    {"saturate(x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14))", 30},
    {"fma(x, y, -z)", 1},
    {"sin(x) + cos(x)", 11},
    {"exp(x) * y + log(y)", 32},
};

std::vector<Expression> half_formulas() {
  std::vector<Expression> out;
  for (const HalfFormula& f : kFormulas) out.push_back(parse_formula(f.text));
  return out;
}

// generate_source in half, the functions named f0, f1, ... (their __half2 forms f0_x2, ...).
std::string half_source(const std::vector<Expression>& formulas, Language lang) {
  std::vector<SourceFunction> functions;
  for (std::size_t i = 0; i < formulas.size(); ++i) {
    SourceFunction f{formulas[i], {}};
    f.options.name = "f" + std::to_string(i);
    f.options.precision = Precision::Half;
    f.options.bake_parameters = true;
    functions.push_back(std::move(f));
  }
  return generate_source(functions, lang);
}

// count_sass (toolchain_test_support.hpp) counts float mnemonics; the half code's arithmetic is
// counted by writing each of its instructions with a float mnemonic first: HADD2 (with the
// conversions HADD2.F32), HMUL2, HFMA2, HMNMX2, VHMNMX, HSET2, HSETP2, F2FP, PLOP3 and ISETP.
// Not counted: moves of constants (HFMA2.MMA d, -RZ, RZ, imm and HADD2 d, -RZ, imm) and PRMT,
// which packs two halves into a register.
std::string with_half_arithmetic_as_float(const std::string& dump) {
  static const char* kHalf[] = {"HADD2", "HMUL2",  "HFMA2", "HMNMX2", "VHMNMX",
                                "HSET2", "HSETP2", "F2FP",  "PLOP3",  "ISETP"};
  std::istringstream lines(dump);
  std::string out;
  for (std::string line; std::getline(lines, line); out += line + "\n") {
    const std::size_t close = line.find("*/");
    if (line.find("/*") == std::string::npos || close == std::string::npos) continue;
    // [@P0] OP d, a, b, ... ;
    std::istringstream words(line.substr(close + 2, line.find(';', close) - close - 2));
    std::string op;
    words >> op;
    if (!op.empty() && op[0] == '@') words >> op;
    bool half = false;
    for (const char* h : kHalf) half = half || op.rfind(h, 0) == 0;
    if (!half) continue;
    std::vector<std::string> operands;
    for (std::string w; std::getline(words, w, ',');) {
      std::erase(w, ' ');
      operands.push_back(w);
    }
    const auto is = [&](std::size_t k, const char* prefix) {
      return operands.size() > k && operands[k].rfind(prefix, 0) == 0;
    };
    const bool literal = operands.size() > 2 && operands[2].find_first_of("0123456789") <= 1;
    const bool move = (op.rfind("HFMA2", 0) == 0 && is(1, "-RZ") && operands[2] == "RZ") ||
                      (op.rfind("HADD2", 0) == 0 && op.find(".F32") == std::string::npos &&
                       (is(1, "-RZ") || is(1, "RZ")) && literal);
    if (!move) line.replace(line.find(op, close), op.size(), "FADD");
  }
  return out;
}

TEST(HalfCompilerCheck, Half2CountsOfTheModel) {
  for (const HalfFormula& f : kFormulas)
    EXPECT_EQ(instruction_count(parse_formula(f.text), InstructionTarget::SassHalf2), f.half2)
        << f.text;
}

TEST(HalfCompilerCheck, Half2SassAgainstNvcc) {
  const auto nvcc = testing::find_tool("nvcc");
  if (!nvcc) GTEST_SKIP() << "skipped: nvcc not found";
  const auto cuobjdump = testing::find_tool("cuobjdump");
  if (!cuobjdump) GTEST_SKIP() << "skipped: cuobjdump not found";
  const std::vector<Expression> formulas = half_formulas();
  std::string src = half_source(formulas, Language::Cuda);
  for (std::size_t i = 0; i < formulas.size(); ++i) {
    const std::size_t n = testing::input_count(formulas[i]);
    std::string args;
    for (std::size_t k = 0; k < n; ++k)
      args += fmt::format("{}in[i * {} + {}]", k ? ", " : "", n, k);
    src += fmt::format(
        "extern \"C\" __global__ void k{0}(const __half2* __restrict__ in, __half2* __restrict__ "
        "out) {{\n  const int i = threadIdx.x;\n  out[i] = f{0}_x2({1});\n}}\n",
        i, args);
  }
  const auto dir = testing::scratch_folder("half_sass");
  testing::write_text(dir / "half.cu", src);
  std::string log;
  ASSERT_EQ(testing::run_command(fmt::format("cd '{}' && '{}' --use_fast_math -arch=sm_90 -cubin "
                                             "-o half.cubin half.cu",
                                             dir.string(), *nvcc),
                                 &log),
            0)
      << log;
  std::string dump;
  ASSERT_EQ(testing::run_command(
                fmt::format("'{}' -sass '{}'", *cuobjdump, (dir / "half.cubin").string()), &dump),
            0)
      << dump;
  const auto counts = testing::count_sass(with_half_arithmetic_as_float(dump));
  std::cout << "| formula | float sass (model) | half2 model | half2 nvcc | per value |\n"
               "| --- | --- | --- | --- | --- |\n";
  for (std::size_t i = 0; i < formulas.size(); ++i) {
    const std::string k = "k" + std::to_string(i);
    const int measured = counts.count(k) ? counts.at(k) : -1;
    const int model = instruction_count(formulas[i], InstructionTarget::SassHalf2);
    std::cout << "| `" << kFormulas[i].text << "` | "
              << instruction_count(formulas[i], InstructionTarget::Sass) << " | " << model << " | "
              << measured << " | " << model / 2.0 << " |\n";
    EXPECT_EQ(measured, model) << kFormulas[i].text;
  }
}

// The 16-bit float type in a SPIR-V binary (OpTypeFloat 16).
bool declares_half(const std::string& spirv) {
  std::vector<std::uint32_t> w(spirv.size() / 4);
  std::memcpy(w.data(), spirv.data(), w.size() * 4);
  for (std::size_t i = 5; i + 2 < w.size();) {
    const std::uint32_t count = w[i] >> 16, op = w[i] & 0xffffu;
    if (count == 0) break;
    if (op == 22 && w[i + 2] == 16) return true;  // OpTypeFloat %id 16
    i += count;
  }
  return false;
}

TEST(HalfCompilerCheck, GlslangAcceptsTheGlslAndHlsl) {
  const auto glslang = testing::find_tool("glslangValidator");
  if (!glslang) GTEST_SKIP() << "skipped: glslangValidator not found";
  const std::vector<Expression> formulas = half_formulas();
  for (const Language lang : {Language::Glsl, Language::Hlsl}) {
    const bool glsl = lang == Language::Glsl;
    std::string src = half_source(formulas, lang);
    src += glsl ? "layout(local_size_x = 1) in;\n"
                  "layout(std430, binding = 0) buffer Data { float data[]; };\nvoid main() {\n"
                : "RWStructuredBuffer<float> data : register(u0);\n[numthreads(1, 1, 1)]\n"
                  "void main() {\n";
    std::size_t offset = formulas.size();
    for (std::size_t i = 0; i < formulas.size(); ++i) {
      std::string args;
      for (std::size_t k = 0; k < testing::input_count(formulas[i]); ++k)
        args +=
            fmt::format("{}{}(data[{}])", k ? ", " : "", glsl ? "float16_t" : "(half)", offset++);
      src += fmt::format("  data[{}] = float(f{}({}));\n", i, i, args);
    }
    src += "}\n";
    const auto dir = testing::scratch_folder(glsl ? "half_glsl" : "half_hlsl");
    const std::string file = glsl ? "half.comp" : "half.hlsl";
    testing::write_text(dir / file, src);
    std::string log;
    const int status = testing::run_command(
        fmt::format("cd '{}' && '{}' -V {} -o half.spv {}", dir.string(), *glslang,
                    glsl ? "" : "-D -Od -S comp -e main --hlsl-enable-16bit-types", file),
        &log);
    ASSERT_EQ(status, 0) << log << "\n" << src;
    EXPECT_TRUE(declares_half(testing::read_text(dir / "half.spv"))) << language_name(lang);
  }
}

// The CUDA __half functions compiled as host code (nvcc, cuda_fp16.h's host arithmetic and the
// helpers' float fallbacks) and run on random half inputs: each result within one half ulp of
// evaluate_half's.
TEST(HalfCompilerCheck, CudaHalfOnTheHostAgainstEvaluateHalf) {
  const auto nvcc = testing::find_tool("nvcc");
  if (!nvcc) GTEST_SKIP() << "skipped: nvcc not found";
  ParseOptions po;
  po.parameters = {"c0", "c1"};
  std::vector<Expression> formulas = {
      parse_formula("r0 + (x - r0) * x^4"),
      parse_formula("c0 + r0 + (c1 * x - r0) * x^4", po),  // the seed's, with fitted constants
      parse_formula("r0 + (1 - r0) * (1 - x)^5"),
      parse_formula("r0 + (1 - r0) * exp2((-5.55473 * x - 6.98316) * x)"),
      parse_formula("2 * x / (x + sqrt(r0 + (1 - r0) * x^2))"),
      parse_formula("fma(r0, x, 0.25) * log2(x + 1) - rsqrt(x + 0.5)"),
      parse_formula("r0 * exp(-x * r0) + sin(x) * cos(r0) + pow(x, r0) - 1 / (x + r0) + log(r0)"),
  };
  formulas[1].parameter_values = {0.0123, 0.98137};
  constexpr int kRows = 400;
  Rng rng(29);
  std::vector<std::array<double, 2>> rows(kRows);  // (r0, x), binary16 values in [1/64, 1]
  std::string inputs;
  for (auto& row : rows) {
    for (double& v : row) v = round_to_half(1.0 / 64 + uniform01(rng) * (1.0 - 1.0 / 64));
    inputs += fmt::format("{:.17g} {:.17g}\n", row[0], row[1]);
  }
  std::string src = "#include <cstdio>\n" + half_source(formulas, Language::Cuda);
  src +=
      "int main(int argc, char** argv) {\n  FILE* in = std::fopen(argv[1], \"r\");\n"
      "  float r0, x;\n  while (std::fscanf(in, \"%f %f\", &r0, &x) == 2) {\n"
      "    const __half hr0 = __float2half(r0), hx = __float2half(x);\n";
  for (std::size_t i = 0; i < formulas.size(); ++i) {
    // Every formula reads r0 and x, in the order of first use.
    const std::string args = formulas[i].variables.front() == "r0" ? "hr0, hx" : "hx, hr0";
    src += fmt::format("    std::printf(\"%04x \", __half_as_ushort(f{}({})));\n", i, args);
  }
  src += "    std::printf(\"\\n\");\n  }\n  return 0;\n}\n";
  const auto dir = testing::scratch_folder("half_host");
  testing::write_text(dir / "host.cu", src);
  testing::write_text(dir / "inputs.txt", inputs);
  std::string log;
  ASSERT_EQ(
      testing::run_command(
          fmt::format("cd '{}' && '{}' -arch=sm_90 -o host host.cu", dir.string(), *nvcc), &log),
      0)
      << log;
  std::string out;
  ASSERT_EQ(testing::run_command(fmt::format("cd '{}' && ./host inputs.txt", dir.string()), &out),
            0)
      << out;
  std::istringstream results(out);
  std::vector<double> max_ulps(formulas.size(), 0.0);
  for (const auto& row : rows) {
    for (std::size_t i = 0; i < formulas.size(); ++i) {
      unsigned bits = 0;
      ASSERT_TRUE(results >> std::hex >> bits) << out;
      const std::vector<double> vars = formulas[i].variables.front() == "r0"
                                           ? std::vector<double>{row[0], row[1]}
                                           : std::vector<double>{row[1], row[0]};
      const double want = evaluate_half(formulas[i], vars),
                   got = static_cast<double>(half_to_float(static_cast<std::uint16_t>(bits)));
      const double ulps = want == got ? 0.0 : std::fabs(got - want) / half_ulp(want);
      max_ulps[i] = std::max(max_ulps[i], ulps);
      EXPECT_LE(ulps, 1.0) << "f" << i << " at r0 = " << row[0] << ", x = " << row[1] << ": host "
                           << got << ", evaluate_half " << want;
    }
  }
  for (std::size_t i = 0; i < formulas.size(); ++i)
    std::cout << "f" << i << ": max difference " << max_ulps[i] << " half ulp over " << kRows
              << " inputs\n";
}

}  // namespace
}  // namespace shaderfit
