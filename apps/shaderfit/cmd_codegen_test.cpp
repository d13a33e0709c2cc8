#include <gtest/gtest.h>

#include "cli_test_util.hpp"

namespace shaderfit::cli::testing {
namespace {

TEST(CmdCodegen, PrintsOneFunction) {
  const CliResult r = run({"codegen", "--lang", "cuda", "--name", "fresnel", "r0 + (1 - cos_theta - r0) * (1 - cos_theta)^4"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("__device__ __forceinline__ float fresnel(float r0, float cos_theta) {"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("fmaf("), std::string::npos) << r.out;
}

// The comment above the code shows the formula for people: float32's shortest constants, and
// one sign in a sum.
TEST(CmdCodegen, CommentShowsShortConstants) {
  const CliResult r = run({"codegen", "--lang", "glsl", "x * 0.5829255932120166 - -0.25"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("// x * 0.5829256 + 0.25\n"), std::string::npos) << r.out;
}

TEST(CmdCodegen, InputsAndParamsKeepTheirNamesAndOrder) {
  const CliResult r = run({"codegen", "--lang", "glsl", "--inputs", "cos_theta,r0", "--params", "s",
                           "r0 + (1 - r0 - s * cos_theta) * (1 - cos_theta)^4"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("float shaderfit_formula(float cos_theta, float r0, float s) {"), std::string::npos) << r.out;
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

TEST(CmdCodegen, UnknownLanguage) {
  const CliResult r = run({"codegen", "--lang", "fortran", "a + b"});
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(line_count(r.err), 1);
  EXPECT_NE(r.err.find("unknown language 'fortran'"), std::string::npos) << r.err;
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
