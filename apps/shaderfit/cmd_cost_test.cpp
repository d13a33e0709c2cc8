#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <regex>

#include "cli_test_util.hpp"

namespace shaderfit::cli::testing {
namespace {

TEST(CmdCost, PrintsCountsPerTargetAndTheListing) {
  const CliResult r = run({"cost", "r0 + (1 - r0) * (1 - cos_theta)^5"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(std::regex_search(r.out, std::regex("\\nsass +6 "))) << r.out;
  EXPECT_TRUE(std::regex_search(r.out, std::regex("\\ngeneric +7 "))) << r.out;
  EXPECT_NE(r.out.find("FADD.FTZ R2, -R0, 1"), std::string::npos) << r.out;
}

TEST(CmdCost, JsonOnStdout) {
  const CliResult r = run(
      {"cost", "--target", "ptx", "--json", "-", "r0 + (1 - cos_theta - r0) * (1 - cos_theta)^4"});
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["targets"]["sass"]["instructions"], 5);
  EXPECT_EQ(j["listing"]["target"], "ptx");
  EXPECT_EQ(j["listing"]["lines"].size(), 5u);
}

TEST(CmdCost, HalfRowIsPerTwoValuesAndSaysWhyWhereThereIsNoHalfForm) {
  const CliResult r = run({"cost", "r0 + (1 - r0) * (1 - cos_theta)^5"});
  ASSERT_EQ(r.status, 0) << r.err;
  // docs/precision.md: Schlick is 7 instructions per __half2 call (two values).
  EXPECT_TRUE(std::regex_search(r.out, std::regex("\\nsass-half2 +7 "))) << r.out;
  const CliResult s = run({"cost", "sign(x) * x"});
  ASSERT_EQ(s.status, 0) << s.err;
  EXPECT_TRUE(std::regex_search(s.out, std::regex("\\nsass-half2 +-  \\(sign has no half form")))
      << s.out;
  const CliResult j = run({"cost", "--json", "-", "sign(x) * x"});
  const std::string why =
      nlohmann::json::parse(j.out)["unavailable"]["sass-half2"].get<std::string>();
  EXPECT_EQ(why.rfind("sign has no half form", 0), 0u) << j.out;
  const CliResult h = run({"cost", "--target", "sass-half2", "sign(x) * x"});
  EXPECT_EQ(h.status, 2);
  EXPECT_NE(h.err.find("sign has no half form"), std::string::npos) << h.err;
}

// AMD RDNA 2 (gfx1030): the counts of the hand-written kernels (docs/cost-model.md, "RDNA").
TEST(CmdCost, Rdna2CountsAsClangCompilesThem) {
  const std::pair<const char*, int> cases[] = {
      {"x*x*x + 1/(x + 2)", 4}, {"exp2(a*x + 0.5)", 2}, {"pow(x, 2.4)", 3}, {"x > 0.5 ? x*x : sqrt(x)", 4}};
  for (const auto& [formula, count] : cases) {
    const CliResult r = run({"cost", "--target", "rdna2", "--json", "-", formula});
    ASSERT_EQ(r.status, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["targets"]["rdna2"]["instructions"], count) << formula;
    EXPECT_EQ(j["listing"]["target"], "rdna2");
    EXPECT_EQ(j["listing"]["lines"].size(), static_cast<std::size_t>(count)) << formula;
  }
  const CliResult t = run({"cost", "--target", "rdna3", "x > 0.5 ? x*x : sqrt(x)"});
  ASSERT_EQ(t.status, 0) << t.err;
  EXPECT_TRUE(std::regex_search(t.out, std::regex("\\nrdna2 +4 "))) << t.out;
  EXPECT_NE(t.out.find("v_cndmask_b32"), std::string::npos) << t.out;
}

TEST(CmdCost, UnknownTargetIsOneLineAndStatus2) {
  const CliResult r = run({"cost", "--target", "x86", "a + b"});
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(line_count(r.err), 1);
  EXPECT_NE(r.err.find("unknown target 'x86' (known: sass, ptx, generic, sass-half2, rdna2, rdna3)"),
            std::string::npos)
      << r.err;
}

TEST(CmdCost, BadFormulaIsOneLineAndStatus2) {
  const CliResult r = run({"cost", "a + * b"});
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(line_count(r.err), 1);
  EXPECT_NE(r.err.find("formula:1:"), std::string::npos) << r.err;
}

// A phase function as a volumetric shader writes it: its cost as written, and the same count as
// the formula it is.
TEST(CmdCost, AShaderFunctionIsCostedAsWritten) {
  const std::string path = scratch_file("hg.glsl", R"(
#define PI 3.14159265
float phase(float mu, float g) {
  float g2 = g * g;
  float inv = inversesqrt(max(1.0 + g2 - 2.0 * g * mu, 1e-6));
  return (1.0 - g2) * inv * inv * inv / (4.0 * PI);
})");
  const CliResult r = run({"cost", "--reference-file", path, "--function", "phase"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("inputs: mu, g"), std::string::npos) << r.out;
  const CliResult f = run(
      {"cost", "--inputs", "mu,g", "(1 - g*g) * rsqrt(max(1 + g*g - 2*g*mu, 1e-6))^3 / 12.566371"});
  ASSERT_EQ(f.status, 0) << f.err;
  const std::regex sass("\\nsass +([0-9]+) ");
  std::smatch a, b;
  ASSERT_TRUE(std::regex_search(r.out, a, sass)) << r.out;
  ASSERT_TRUE(std::regex_search(f.out, b, sass)) << f.out;
  EXPECT_EQ(a[1].str(), b[1].str());
}

// --inputs orders a shader function's parameters and picks one of an overloaded name (HDRP's
// V_SmithJointGGXAniso with and without its precomputed part).
TEST(CmdCost, InputsPickAnOverloadOfTheShaderFunction) {
  const std::string path = scratch_file("overloads.hlsl", R"(
float V(float a, float b, float part) { return 0.5 / (a * part + b); }
float V(float a, float b) { return V(a, b, sqrt(a)); }
)");
  const CliResult r = run({"cost", "--reference-file", path, "--function", "V", "--inputs", "b,a"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("inputs: b, a"), std::string::npos) << r.out;
  expect_bad_input({"cost", "--reference-file", path, "--function", "V"},
                   "function 'V' is defined 2 times");
}

// Six unrolled Newton steps are a tree of thousands of nodes (each step reads the last twice)
// but a few instructions each: costed, the formula not printed (fuzz5's cbrt and CIELAB).
TEST(CmdCost, AnUnrolledNewtonIterationIsCostedThoughItsTreeIsLarge) {
  const std::string path = scratch_file("newton.hlsl", R"(
float CbrtNewton(float v) {
  float y = 0.5 + 0.5 * v;
  [unroll] for (int it = 0; it < 6; ++it) { float y2 = y * y; y = (2.0 * y + v / y2) / 3.0; }
  return y;
})");
  const CliResult r = run({"cost", "--reference-file", path, "--function", "CbrtNewton"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("formula: not shown: 6557 nodes written out"), std::string::npos) << r.out;
  const std::regex sass("\\nsass +([0-9]+) ");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(r.out, m, sass)) << r.out;
  EXPECT_LE(std::stoi(m[1].str()), 36);
}

TEST(CmdCost, AShaderFunctionThatCannotBeCostedIsOneLineAndStatus2) {
  const std::string path = scratch_file("floor.glsl", "float f(float x) { return floor(x) * x; }");
  expect_bad_input({"cost", "--reference-file", path, "--function", "f"},
                   "--reference-file: f cannot be costed as written: it calls floor");
  expect_bad_input({"cost", "--reference-file", path}, "--function: name the function");
  expect_bad_input({"cost", "--reference-file", path, "--function", "f", "x + 1"},
                   "give a formula or --reference-file, not both");
  expect_bad_input({"cost", "--function", "f", "x + 1"}, "--function names a function");
  expect_bad_input({"cost"}, "give a formula, or --reference-file with --function");
}

}  // namespace
}  // namespace shaderfit::cli::testing
