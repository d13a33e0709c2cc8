// Formulas with per-material inputs printed in two parts (codegen.hpp, CodegenOptions::uniform):
// compiled by every compiler present, each part counted where the compiler's output is counted
// (nvcc SASS and PTX, glslang SPIR-V), and the C++ of the two parts run on 10^5 random inputs
// against the one-part function.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <iostream>

#include "codegen/toolchain_test_support.hpp"
#include "shaderfit/codegen/codegen.hpp"
#include "shaderfit/core/random.hpp"
#include "shaderfit/cost/per_material.hpp"
#include "shaderfit/expr/parse.hpp"

namespace shaderfit {
namespace {

struct Case {
  const char* formula;
  std::vector<std::string> inputs, uniform;
  std::vector<std::pair<double, double>> box;  // per input
  std::vector<std::string> params = {};
  std::vector<double> values = {};
};

const std::vector<Case>& cases() {
  static const std::vector<Case> c = {
      {"1/(3.14159*alpha^2) * pow(NoH, 2/alpha^2 - 2)",
       {"NoH", "alpha"},
       {"alpha"},
       {{0.01, 1}, {0.05, 0.5}}},
      // Walter's G1 rational piece in a = nv / (alpha sqrt(1 - nv^2)), 1/alpha per material.
      {"(3.535*(nv/alpha*rsqrt(1 - nv^2)) + 2.181*(nv/alpha*rsqrt(1 - nv^2))^2)/(1 + "
       "2.276*(nv/alpha*rsqrt(1 - nv^2)) + 2.577*(nv/alpha*rsqrt(1 - nv^2))^2)",
       {"nv", "alpha"},
       {"alpha"},
       {{0.05, 0.99}, {0.05, 1}}},
      {"exp((n + 0.775)*(x - 1))", {"x", "n"}, {"n"}, {{0, 1}, {1, 256}}},
      {"f0 + (1 - f0)*(1 - c)^5", {"f0", "c"}, {"f0"}, {{0.02, 0.2}, {0, 1}}},
      {"0.5/(nl*sqrt(nv^2*(1 - alpha^2) + alpha^2) + nv*sqrt(nl^2*(1 - alpha^2) + alpha^2))",
       {"nl", "nv", "alpha"},
       {"alpha"},
       {{0.05, 1}, {0.05, 1}, {0.02, 1}}},
      {"erf(k*alpha) * x + c*alpha^2 + rsqrt(alpha + x)",
       {"x", "alpha"},
       {"alpha"},
       {{0, 2}, {0.1, 3}},
       {"k", "c"},
       {1.5, -0.25}},
  };
  return c;
}

Expression parsed(const Case& c) {
  ParseOptions po;
  po.variables = c.inputs;
  po.parameters = c.params;
  po.parameter_values = c.values;
  return parse_formula(c.formula, po);
}

SourceFunction two_part(const Case& c, const std::string& name) {
  SourceFunction f{parsed(c), {}};
  f.options.name = name;
  f.options.bake_parameters = true;
  f.options.uniform = c.uniform;
  return f;
}

bool is_uniform(const Case& c, const std::string& v) {
  return std::find(c.uniform.begin(), c.uniform.end(), v) != c.uniform.end();
}

// The call of the two parts of case i, its inputs read as `in(k)` for input k.
template <typename In>
std::string two_part_call(const Case& c, const std::string& name, In in) {
  std::string varying, uniform;
  for (std::size_t k = 0; k < c.inputs.size(); ++k) {
    std::string& list = is_uniform(c, c.inputs[k]) ? uniform : varying;
    list += (list.empty() ? "" : ", ") + in(k);
  }
  return name + "(" + varying + ", " + material_function_name(name) + "(" + uniform + "))";
}

TEST(TwoPartCheck, CppTwoPartsEqualTheOnePartFormulaOnRandomInputs) {
  constexpr std::size_t kRows = 100'000;
  const auto dir = testing::scratch_folder("two_part_cpp");
  std::vector<SourceFunction> functions;
  std::string calls;
  for (std::size_t i = 0; i < cases().size(); ++i) {
    const Case& c = cases()[i];
    const std::string f = "f" + std::to_string(i), g = "g" + std::to_string(i);
    functions.push_back(two_part(c, f));
    SourceFunction one{parsed(c), {}};
    one.options.name = g;
    one.options.bake_parameters = true;
    functions.push_back(std::move(one));
    std::string args;
    for (std::size_t k = 0; k < c.inputs.size(); ++k)
      args += (k ? ", " : "") + fmt::format("in[{}]", k);
    calls += fmt::format(
        "  if (which == {}) {{ out[0] = {}; out[1] = {}({}); }}\n", i,
        two_part_call(c, f, [](std::size_t k) { return fmt::format("in[{}]", k); }), g, args);
  }
  std::string src = generate_source(functions, Language::Cpp);
  src +=
      "#include <cstdio>\n#include <cstdlib>\nint main(int argc, char** argv) {\n"
      "  const int which = std::atoi(argv[1]), n = std::atoi(argv[2]);\n"
      "  float in[8], out[2];\n"
      "  while (std::fread(in, sizeof(float), n, stdin) == static_cast<std::size_t>(n)) {\n" +
      calls + "    std::fwrite(out, sizeof(float), 2, stdout);\n  }\n}\n";
  testing::write_text(dir / "two_part.cpp", src);

  const auto compilers = testing::cpp_compilers();
  for (const auto& [compiler, cxx_path] : compilers) {
    const std::string* cxx = &cxx_path;
    const auto exe = dir / compiler;
    std::string log;
    ASSERT_EQ(testing::run_command(
                  "'" + *cxx + "' -std=c++17 -O1 -ffp-contract=off -Wall -pedantic -Werror -o '" +
                      exe.string() + "' '" + (dir / "two_part.cpp").string() + "'",
                  &log),
              0)
        << compiler << ": " << log << "\n"
        << src;
    for (std::size_t i = 0; i < cases().size(); ++i) {
      const Case& c = cases()[i];
      Rng rng(7 + i);
      std::vector<float> in(kRows * c.inputs.size());
      for (std::size_t r = 0; r < kRows; ++r)
        for (std::size_t k = 0; k < c.inputs.size(); ++k)
          in[r * c.inputs.size() + k] =
              static_cast<float>(uniform(rng, c.box[k].first, c.box[k].second));
      std::string bytes(in.size() * 4, '\0');
      std::memcpy(bytes.data(), in.data(), bytes.size());
      testing::write_text(dir / "in.bin", bytes);
      ASSERT_EQ(testing::run_command(fmt::format("'{}' {} {} < '{}' > '{}'", exe.string(), i,
                                                 c.inputs.size(), (dir / "in.bin").string(),
                                                 (dir / "out.bin").string())),
                0);
      const std::string out = testing::read_text(dir / "out.bin");
      ASSERT_EQ(out.size(), kRows * 8);
      double worst = 0;
      for (std::size_t r = 0; r < kRows; ++r) {
        float two, one;
        std::memcpy(&two, &out[r * 8], 4);
        std::memcpy(&one, &out[r * 8 + 4], 4);
        // Float32 rounding of what each computes: a few ulp of the value, and for a value that
        // is an exponential (2^y) the rounding of its argument y, |log2 value| ulps of 2^-24.
        const double scale = std::abs(one) * (1.0 + std::abs(std::log2(std::abs(one) + 1e-38)));
        const double err = std::abs(static_cast<double>(two) - one);
        ASSERT_TRUE(std::isfinite(two) == std::isfinite(one)) << c.formula << " row " << r;
        if (!std::isfinite(one)) continue;
        const double ulps = err / (scale * 0x1p-24 + 1e-40);
        worst = std::max(worst, ulps);
      }
      EXPECT_LE(worst, 16.0) << compiler << ": " << c.formula;
      std::cout << compiler << ", two parts vs one, " << c.formula << ": max " << worst
                << " rounding units\n";
    }
  }
  if (compilers.empty()) GTEST_SKIP() << "skipped: no C++ compiler found";
}

TEST(TwoPartCheck, EachPartAsTheCompilersCountIt) {
  const auto nvcc = testing::find_tool("nvcc");
  const auto glslang = testing::find_tool("glslangValidator");
  if (!nvcc && !glslang)
    GTEST_SKIP() << "skipped: nvcc not found; skipped: glslangValidator not found";
  std::vector<SourceFunction> functions;
  std::vector<MaterialSplit> splits;
  for (std::size_t i = 0; i < cases().size(); ++i) {
    functions.push_back(two_part(cases()[i], "f" + std::to_string(i)));
    splits.push_back(split_per_material(functions.back().expression, cases()[i].uniform));
  }
  auto model = [&](std::size_t i, InstructionTarget t) {
    return split_instruction_count(functions[i].expression, cases()[i].uniform, t);
  };

  if (nvcc) {
    // Per case a kernel for each part: kp<i> reads the values from memory and runs the per-pixel
    // function; km<i> computes the values and stores them.
    const auto dir = testing::scratch_folder("two_part_cuda");
    std::string src = generate_source(functions, Language::Cuda);
    for (std::size_t i = 0; i < cases().size(); ++i) {
      const Case& c = cases()[i];
      const std::string f = "f" + std::to_string(i), type = material_type_name(f);
      const MaterialSplit& s = splits[i];
      std::string fill, varying, uniform, store;
      std::size_t n = 0;
      for (const MaterialValue& v : s.values)
        fill += fmt::format("  m.{} = in[i * 8 + {}];\n", v.name, n++);
      for (const std::string& v : c.inputs)
        (is_uniform(c, v) ? uniform : varying) += fmt::format(
            "{}in[i * 8 + {}]", (is_uniform(c, v) ? uniform : varying).empty() ? "" : ", ", n++);
      for (std::size_t k = 0; k < s.values.size(); ++k)
        store += fmt::format("  out[i * 8 + {}] = m.{};\n", k, s.values[k].name);
      src += fmt::format(
          "extern \"C\" __global__ void kp{0}(const float* __restrict__ in, float* __restrict__ "
          "out) {{\n"
          "  const int i = threadIdx.x;\n  {1} m;\n{2}  out[i] = {0}({3}, m);\n}}\n"
          "extern \"C\" __global__ void km{0}(const float* __restrict__ in, float* __restrict__ "
          "out) {{\n"
          "  const int i = threadIdx.x;\n  const {1} m = {4}({5});\n{6}}}\n",
          f, type, fill, varying, material_function_name(f), uniform, store);
    }
    testing::write_text(dir / "all.cu", src);
    std::string log;
    ASSERT_EQ(
        testing::run_command(
            fmt::format(
                "cd '{}' && '{}' --use_fast_math -arch=sm_90 -cubin -keep -o all.cubin all.cu",
                dir.string(), *nvcc),
            &log),
        0)
        << log << "\n"
        << src;
    const auto ptx = testing::count_ptx(testing::read_text(dir / "all.ptx"));
    std::map<std::string, int> sass;
    std::string dump_log;
    const testing::SassDump dumped = testing::dump_sass(dir / "all.cubin", &sass, &dump_log);
    ASSERT_NE(dumped, testing::SassDump::Failed) << dump_log;
    if (dumped == testing::SassDump::Absent)
      std::cout << "skipped: cuobjdump not found (no SASS counts)\n";
    for (std::size_t i = 0; i < cases().size(); ++i) {
      const std::string k = "f" + std::to_string(i);
      const SplitCost s = model(i, InstructionTarget::Sass), p = model(i, InstructionTarget::Ptx);
      EXPECT_EQ(ptx.at("kp" + k), p.per_pixel) << cases()[i].formula;
      EXPECT_EQ(ptx.at("km" + k), p.per_material) << cases()[i].formula;
      if (dumped == testing::SassDump::Done) {
        EXPECT_EQ(sass.at("kp" + k), s.per_pixel) << cases()[i].formula;
        EXPECT_EQ(sass.at("km" + k), s.per_material) << cases()[i].formula;
      }
      std::cout << cases()[i].formula << ": per pixel model " << s.per_pixel << " SASS, nvcc "
                << (sass.empty() ? -1 : sass.at("kp" + k)) << "; per material model "
                << s.per_material << ", nvcc " << (sass.empty() ? -1 : sass.at("km" + k)) << "\n";
    }
  } else {
    std::cout << "skipped: nvcc not found\n";
  }

  if (!glslang) {
    std::cout << "skipped: glslangValidator not found\n";
    return;
  }
  for (Language lang : {Language::Glsl, Language::Hlsl}) {
    const bool glsl = lang == Language::Glsl;
    const auto dir = testing::scratch_folder(glsl ? "two_part_glsl" : "two_part_hlsl");
    std::string src = generate_source(functions, lang);
    src += glsl ? "layout(local_size_x = 1) in;\nlayout(std430, binding = 0) buffer Data { float "
                  "data[]; };\n"
                : "RWStructuredBuffer<float> data : register(u0);\n";
    std::string body;
    std::size_t offset = cases().size();
    for (std::size_t i = 0; i < cases().size(); ++i)
      body += fmt::format("  data[{}] = {};\n", i,
                          two_part_call(cases()[i], "f" + std::to_string(i), [&](std::size_t) {
                            return fmt::format("data[{}]", offset++);
                          }));
    src += glsl ? "void main() {\n" + body + "}\n"
                : "[numthreads(1, 1, 1)]\nvoid main() {\n" + body + "}\n";
    const std::string file = glsl ? "all.comp" : "all.hlsl";
    testing::write_text(dir / file, src);
    std::string log;
    ASSERT_EQ(
        testing::run_command(fmt::format("cd '{}' && '{}' -V {} -o all.spv {}", dir.string(),
                                         *glslang, glsl ? "" : "-D -Od -S comp -e main", file),
                             &log),
        0)
        << log << "\n"
        << src;
    const auto counts = testing::count_spirv(testing::read_text(dir / "all.spv"));
    // A function's count includes the erf helper's instructions once per call (its own function
    // in SPIR-V), as the model counts them.
    auto with_calls = [&](const std::string& function, const std::string& text) {
      int calls = 0;
      const std::string call = "sf_erf(";
      for (std::size_t at = text.find(call); at != std::string::npos; at = text.find(call, at + 1))
        ++calls;
      return counts.at(function) + calls * (calls > 0 ? counts.at("sf_erf") : 0);
    };
    for (std::size_t i = 0; i < cases().size(); ++i) {
      const std::string f = "f" + std::to_string(i);
      const SplitCost g = model(i, InstructionTarget::Generic);
      // The printed parts: the per-material function ends where the per-pixel one starts.
      CodegenOptions o = functions[i].options;
      o.language = lang;
      std::string text = generate_function(functions[i].expression, o);
      const std::size_t helper = text.find("}\n\n");
      if (text.find("float sf_erf(") != std::string::npos) text = text.substr(helper + 3);
      const std::size_t pixel = text.find("float " + f + "(");
      EXPECT_EQ(with_calls(f, text.substr(pixel)), g.per_pixel)
          << language_name(lang) << ": " << cases()[i].formula;
      EXPECT_EQ(with_calls(material_function_name(f), text.substr(0, pixel)), g.per_material)
          << language_name(lang) << ": " << cases()[i].formula;
    }
  }
}

}  // namespace
}  // namespace shaderfit
