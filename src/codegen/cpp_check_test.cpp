// A search front through every compiler on the machine, and the generated C++ run on the seed's
// data against the evaluator (float32, within a few ulp).
#include <gtest/gtest.h>

#include <cstring>
#include <iostream>

#include "codegen/compiler_harness_test_support.hpp"
#include "shaderfit/core/random.hpp"
#include "shaderfit/data/fresnel_seed.hpp"
#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/expr/parse.hpp"

namespace shaderfit {
namespace {

// The members of a search front over r0 and cos_theta; `s` is a fitted parameter (0.25). The
// last one has sign, copysign and select.
const char* const kFront[] = {"r0 + (1 - r0) * (1 - cos_theta)^5",
                              "r0 + (1 - cos_theta - r0) * (1 - cos_theta)^4",
                              "r0 + (1 - r0 - s * cos_theta) * (1 - cos_theta)^4",
                              "r0 + (1 - r0) * exp2((-5.55473 * cos_theta - 6.98316) * cos_theta)",
                              "r0 + (1 - r0) * (1 - cos_theta)^5 / (1 + 0.5 * sqrt(cos_theta))",
                              "copysign(r0, cos_theta - 0.5) * select(cos_theta >= 0.3, "
                              "(1 - cos_theta)^5, 2 + sign(cos_theta - 0.1))"};

std::int64_t ulp_distance(float a, float b) {
  std::int32_t x, y;
  std::memcpy(&x, &a, 4);
  std::memcpy(&y, &b, 4);
  if (x < 0) x = std::numeric_limits<std::int32_t>::min() - x;
  if (y < 0) y = std::numeric_limits<std::int32_t>::min() - y;
  return std::llabs(static_cast<std::int64_t>(x) - y);
}

TEST(CompilerCheck, FrontCompilesEverywhereAndCppAgreesWithEvaluator) {
  const auto dir = testing::scratch_folder("front");
  std::vector<Expression> exprs;
  for (const char* formula : kFront) {
    ParseOptions po;
    po.variables = {"r0", "cos_theta"};
    if (std::strstr(formula, " s ") != nullptr) {
      po.parameters = {"s"};
      po.parameter_values = {0.25};
    }
    exprs.push_back(parse_formula(formula, po));
  }

  if (const auto nvcc = testing::find_tool("nvcc")) {
    const auto r = testing::compile_cuda(exprs, *nvcc, "front_cuda");
    EXPECT_TRUE(r.ok) << r.log;
  } else {
    std::cout << "skipped: nvcc not found\n";
  }
  if (const auto glslang = testing::find_tool("glslangValidator")) {
    for (Language l : {Language::Glsl, Language::Hlsl}) {
      const auto r = testing::compile_spirv(exprs, l, *glslang, "front_spirv");
      EXPECT_TRUE(r.ok) << r.log;
    }
  } else {
    std::cout << "skipped: glslangValidator not found\n";
  }
  std::cout << "skipped: metal not found (Metal output is checked for form only)\n";

  std::optional<std::string> cxx = testing::find_tool("c++");
  if (!cxx) cxx = testing::find_tool("g++");
  if (!cxx) GTEST_SKIP() << "skipped: c++ not found";

  // The seed's data, in float32, as the evaluator and the compiled functions see it.
  Rng rng(1);
  const Dataset d = make_fresnel_seed_dataset(rng);
  const std::size_t rows = d.rows();
  std::vector<float> r0(rows), cs(rows);
  for (std::size_t i = 0; i < rows; ++i) {
    r0[i] = static_cast<float>(d.numeric("r0").values[i]);
    cs[i] = static_cast<float>(d.numeric("cos_theta").values[i]);
  }
  // The file exactly as printed (its own includes), then the entry point: main and its <cstdio>.
  std::vector<SourceFunction> functions;
  std::string calls;
  for (std::size_t i = 0; i < exprs.size(); ++i) {
    SourceFunction f{exprs[i], {}};
    f.options.name = "f" + std::to_string(i);
    f.options.bake_parameters = true;  // s has its fitted value
    functions.push_back(std::move(f));
    calls += "    out[" + std::to_string(i) + "] = f" + std::to_string(i) + "(in[0], in[1]);\n";
  }
  std::string src = generate_source(functions, Language::Cpp);
  src += "#include <cstdio>\nint main() {\n  float in[2], out[" + std::to_string(exprs.size()) +
         "];\n"
         "  while (std::fread(in, sizeof(float), 2, stdin) == 2) {\n" +
         calls + "    std::fwrite(out, sizeof(float), " + std::to_string(exprs.size()) +
         ", stdout);\n  }\n}\n";
  testing::write_text(dir / "front.cpp", src);
  std::string log;
  ASSERT_EQ(testing::run_command("'" + *cxx + "' -std=c++17 -O1 -Wall -pedantic -Werror -o '" +
                                     (dir / "front").string() + "' '" +
                                     (dir / "front.cpp").string() + "'",
                                 &log),
            0)
      << log;
  std::string input(rows * 8, '\0');
  for (std::size_t i = 0; i < rows; ++i) {
    std::memcpy(&input[i * 8], &r0[i], 4);
    std::memcpy(&input[i * 8 + 4], &cs[i], 4);
  }
  testing::write_text(dir / "in.bin", input);
  ASSERT_EQ(
      testing::run_command("'" + (dir / "front").string() + "' < '" + (dir / "in.bin").string() +
                           "' > '" + (dir / "out.bin").string() + "'"),
      0);
  const std::string output = testing::read_text(dir / "out.bin");
  ASSERT_EQ(output.size(), rows * exprs.size() * 4);

  const float* columns[] = {r0.data(), cs.data()};
  for (std::size_t f = 0; f < exprs.size(); ++f) {
    std::vector<float> expected(rows);
    evaluate(exprs[f], columns, expected, {.threads = 1});
    std::int64_t worst = 0;
    for (std::size_t i = 0; i < rows; ++i) {
      float got;
      std::memcpy(&got, &output[(i * exprs.size() + f) * 4], 4);
      worst = std::max(worst, ulp_distance(got, expected[i]));
    }
    // Within a few ulp: fma against a*b + c, and the evaluator's SIMD exp2 is itself within a
    // few ulp of exp2.
    EXPECT_LE(worst, 8) << kFront[f];
    std::cout << "C++ vs evaluator, " << kFront[f] << ": max " << worst << " ulp\n";
  }
}

// asin, acos, atan, atan2, tanh and erf in C++ (std::) and in Metal (its erf the helper), each
// compiled by every C++ compiler present (the Metal text with <cmath> in place of metal_stdlib,
// which is C++ as far as these functions go), run on random inputs and compared with the
// evaluator. nvcc and glslang compile them in CompilerCheck.LibraryFunctionsAgainstNvccAndGlslang.
TEST(CompilerCheck, LibraryFunctionsInCppAndMetalAgreeWithEvaluator) {
  const char* const formulas[] = {"asin(x) * y + acos(y)", "atan(3 * x) - atan2(y, x)",
                                  "tanh(2 * x + y)", "erf(2 * x) + erf(y - 0.5) * x",
                                  "acos(-x * y) + atan(x, y - 0.25)"};
  std::vector<Expression> exprs;
  for (const char* f : formulas) exprs.push_back(parse_formula(f));
  Rng rng(3);
  const std::size_t rows = 4096;
  std::vector<float> xs(rows), ys(rows);
  for (std::size_t i = 0; i < rows; ++i) {
    xs[i] = static_cast<float>(uniform(rng, -1.0, 1.0));
    ys[i] = static_cast<float>(uniform(rng, -1.0, 1.0));
  }
  std::vector<std::vector<float>> expected(exprs.size(), std::vector<float>(rows));
  const float* columns[] = {xs.data(), ys.data()};
  for (std::size_t f = 0; f < exprs.size(); ++f)
    evaluate(exprs[f], columns, expected[f], {.threads = 1});
  std::string input(rows * 8, '\0');
  for (std::size_t i = 0; i < rows; ++i) {
    std::memcpy(&input[i * 8], &xs[i], 4);
    std::memcpy(&input[i * 8 + 4], &ys[i], 4);
  }
  const auto dir = testing::scratch_folder("library_cpp");
  testing::write_text(dir / "in.bin", input);

  const auto compilers = testing::cpp_compilers();
  for (const auto& [compiler, cxx_path] : compilers) {
    const std::string* cxx = &cxx_path;
    for (Language lang : {Language::Cpp, Language::Metal}) {
      std::vector<SourceFunction> functions;
      std::string calls;
      for (std::size_t i = 0; i < exprs.size(); ++i) {
        SourceFunction f{exprs[i], {}};
        f.options.name = "f" + std::to_string(i);
        functions.push_back(std::move(f));
        calls += "    out[" + std::to_string(i) + "] = f" + std::to_string(i) + "(in[0], in[1]);\n";
      }
      std::string src = generate_source(functions, lang);
      if (lang == Language::Metal) {
        const std::string head = "#include <metal_stdlib>\nusing namespace metal;\n";
        ASSERT_EQ(src.rfind(head, 0), 0u) << src;
        src = "#include <cmath>\nusing namespace std;\n" + src.substr(head.size());
      }
      src += "#include <cstdio>\nint main() {\n  float in[2], out[" + std::to_string(exprs.size()) +
             "];\n  while (std::fread(in, sizeof(float), 2, stdin) == 2) {\n" + calls +
             "    std::fwrite(out, sizeof(float), " + std::to_string(exprs.size()) +
             ", stdout);\n  }\n}\n";
      const std::string name = std::string(compiler) + "_" + std::string(language_name(lang));
      testing::write_text(dir / (name + ".cpp"), src);
      std::string log;
      ASSERT_EQ(testing::run_command("'" + *cxx +
                                         "' -std=c++17 -O1 -ffp-contract=off -Wall "
                                         "-pedantic -Werror -o '" +
                                         (dir / name).string() + "' '" +
                                         (dir / (name + ".cpp")).string() + "'",
                                     &log),
                0)
          << name << ": " << log << "\n"
          << src;
      ASSERT_EQ(
          testing::run_command("'" + (dir / name).string() + "' < '" + (dir / "in.bin").string() +
                               "' > '" + (dir / (name + ".bin")).string() + "'"),
          0);
      const std::string output = testing::read_text(dir / (name + ".bin"));
      ASSERT_EQ(output.size(), rows * exprs.size() * 4);
      for (std::size_t f = 0; f < exprs.size(); ++f) {
        double worst = 0;
        for (std::size_t i = 0; i < rows; ++i) {
          float got;
          std::memcpy(&got, &output[(i * exprs.size() + f) * 4], 4);
          const double want = expected[f][i];
          worst = std::max(worst, std::abs(got - want) / std::max(1.0, std::abs(want)));
        }
        // A few float32 ulps: each side's functions are within 3 ulp (the helper 1.32), and
        // the sums add their roundings.
        EXPECT_LE(worst, 1e-6) << name << ": " << formulas[f];
        std::cout << name << " vs evaluator, " << formulas[f] << ": max " << worst << "\n";
      }
    }
  }
  if (compilers.empty()) GTEST_SKIP() << "skipped: no C++ compiler found";
}

}  // namespace
}  // namespace shaderfit
