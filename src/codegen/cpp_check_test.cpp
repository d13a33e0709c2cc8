// A search front through every compiler on the machine, and the generated C++ run on the seed's
// data against the evaluator (float32, within a few ulp).
#include <gtest/gtest.h>

#include <cstring>
#include <iostream>

#include "codegen/compiler_harness_test_support.hpp"
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

}  // namespace
}  // namespace shaderfit
