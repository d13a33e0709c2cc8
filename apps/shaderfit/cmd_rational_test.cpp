#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "cli_test_util.hpp"

namespace shaderfit::cli {
namespace {

using testing::CliResult;
using testing::line_count;
using testing::run;

std::vector<std::string> with(std::vector<std::string> a, const std::vector<std::string>& more) {
  a.insert(a.end(), more.begin(), more.end());
  return a;
}

const std::vector<std::string> kSchlick = {"rational",  "--target", "fresnel-dielectric-f0",
                                           "--cond",    "f(0)=1",   "--cond",
                                           "f(1)=F0",   "--cond",   "f'(1)=0",
                                           "--cond",    "f''(1)=0", "--cond",
                                           "f'''(1)=0", "--cond",   "f^(4)(1)=0"};

TEST(CliRational, SchlickFresnelForEveryF0) {
  CliResult r = run(with(kSchlick, {"--form", "5/0", "--transform", "1 - cos", "--param",
                                    "F0=0.02,0.04,0.5,0.9", "--json", "-"}));
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["runs"].size(), 4u);
  EXPECT_EQ(j["runs"][1]["results"][0]["formula"], "0.04 + 0.96 * (1 - cos)^5");
  EXPECT_EQ(j["runs"][2]["results"][0]["formula"], "0.5 + 0.5 * (1 - cos)^5");
  EXPECT_EQ(j["parametric"][0]["formula"], "F0 + (1 - F0) * (1 - cos)^5");
  EXPECT_TRUE(j["parametric"][0]["all_rational"].get<bool>());
}

TEST(CliRational, SchlickGeometricAttenuation) {
  CliResult r = run({"rational", "--target", "smith-ggx-g1", "--param", "alpha=0.5", "--param",
                     "k=0.1,0.3,0.6", "--form", "1/1", "--cond", "G(0)=0", "--cond", "G(1)=1",
                     "--cond", "G'(0)=1/k"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("rational in k: v / (k + (1 - k) * v)"), std::string::npos) << r.out;
}

TEST(CliRational, EnumeratesFormsWithAParetoFront) {
  CliResult r =
      run({"rational", "--target", "fresnel-dielectric", "--param", "ior=1.5", "--cond", "f(0)=1",
           "--cond", "f(1)=ref", "--cond", "f'(1)=ref", "--cond", "int(0,1)=ref"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("2/1 in 1 - cos"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("0/3"), std::string::npos);
  EXPECT_NE(r.out.find("Pareto front"), std::string::npos);
}

TEST(CliRational, RationalMinimaxOfExpEquioscillates) {
  CliResult r = run({"rational", "--target", "exp", "--domain", "-1,1", "--form", "2/2",
                     "--minimax", "--json", "-"});
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  const auto& m = j["runs"][0]["results"][0]["minimax"];
  ASSERT_EQ(m["points"].size(), 6u);
  EXPECT_TRUE(m["converged"].get<bool>());
  EXPECT_LT(m["spread"].get<double>(), 1e-6);
  for (std::size_t i = 1; i < 6; ++i)
    EXPECT_LT(m["errors"][i - 1].get<double>() * m["errors"][i].get<double>(), 0);
  EXPECT_NEAR(m["max_error"].get<double>(), 8.69e-5, 1e-7);
}

TEST(CliRational, MinimaxKeepsConditionsAndListsTargets) {
  CliResult r =
      run({"rational", "--target", "fresnel-dielectric-f0", "--param", "F0=0.04", "--cond",
           "f(0)=1", "--cond", "f(1)=F0", "--form", "4/0", "--transform", "1 - cos", "--minimax"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("alternation:"), std::string::npos) << r.out;
  CliResult l = run({"rational", "--list-targets"});
  EXPECT_EQ(l.status, 0);
  EXPECT_NE(l.out.find("smith-ggx-g1"), std::string::npos);
}

// Targets in the reference language: functions a built-in does not cover, minimax forms of them.
TEST(CliRational, ReferenceLanguageTargetsGetMinimaxForms) {
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"--target", "erf(x)", "--domain", "0,3", "--form", "3/3"},
        std::vector<std::string>{"--target", "acos(x)", "--domain", "x=0:0.9", "--form", "2/2"}}) {
    CliResult r = run(with(with({"rational"}, args), {"--minimax", "--json", "-"}));
    ASSERT_EQ(r.status, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["target"], args[1]);
    const auto& m = j["runs"][0]["results"][0]["minimax"];
    EXPECT_TRUE(m["converged"].get<bool>()) << args[1];
    EXPECT_EQ(m["points"].size(), 6u + (args[5] == "3/3" ? 2u : 0u)) << args[1];
    EXPECT_LT(m["spread"].get<double>(), 1e-6) << args[1];
  }
}

// Kernel conditions on a reference-language target use its exact derivatives: f, f', f'' of
// acos at 0 are pi/2, -1, 0 (its Taylor polynomial), and of erf(x / sqrt(2)) at 0 are 0,
// sqrt(2 / pi), 0.
TEST(CliRational, DerivativeConditionsOnAReferenceFormulaAreAnalytic) {
  CliResult r =
      run({"rational", "--target", "acos(t)", "--var", "t", "--domain", "-0.5,0.5", "--form", "2/0",
           "--cond", "f(0)=ref", "--cond", "f'(0)=ref", "--cond", "f''(0)=ref", "--json", "-"});
  ASSERT_EQ(r.status, 0) << r.err;
  auto p = nlohmann::json::parse(r.out)["runs"][0]["results"][0]["numerator"];
  EXPECT_NEAR(p[0].get<double>(), std::acos(0.0), 1e-15);
  EXPECT_NEAR(p[1].get<double>(), -1.0, 1e-15);
  EXPECT_NEAR(p[2].get<double>(), 0.0, 1e-15);
  r = run({"rational", "--target", "erf(x / sqrt(2))", "--domain", "x=-1:1", "--form", "1/0",
           "--cond", "f(0)=ref", "--cond", "f'(0)=ref", "--json", "-"});
  ASSERT_EQ(r.status, 0) << r.err;
  p = nlohmann::json::parse(r.out)["runs"][0]["results"][0]["numerator"];
  EXPECT_NEAR(p[1].get<double>(), std::sqrt(2 / std::acos(-1.0)), 1e-15);
}

// A shader function as the target: its parameter without a --param value is the variable.
TEST(CliRational, ShaderFunctionTarget) {
  const std::string file = testing::scratch_file("schlick.glsl",
                                                 "float F(float f0, float VdotH) {\n"
                                                 "  float m = clamp(1.0 - VdotH, 0.0, 1.0);\n"
                                                 "  return f0 + (1.0 - f0) * pow(m, 5.0);\n"
                                                 "}\n");
  CliResult r = run({"rational",  "--reference-file", file,         "--function", "F",
                     "--param",   "f0=0.04",          "--form",     "5/0",        "--transform",
                     "1 - VdotH", "--cond",           "f(0)=ref",   "--cond",     "f(1)=ref",
                     "--cond",    "f'(1)=0",          "--cond",     "f''(1)=0",   "--cond",
                     "f'''(1)=0", "--cond",           "f^(4)(1)=0", "--json",     "-"});
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["variable"], "VdotH");
  EXPECT_EQ(j["runs"][0]["results"][0]["formula"], "0.04 + 0.96 * (1 - VdotH)^5");
}

// Bad input: one line naming the problem and where it is, exit status 2.
struct BadInput {
  const char* name;
  std::vector<std::string> args;
  const char* expect;
};

TEST(CliRational, BadInputIsOneLineAndStatusTwo) {
  const std::vector<BadInput> cases = {
      {"more conditions than coefficients",
       {"rational", "--target", "exp", "--form", "1/0", "--cond", "f(0)=1", "--cond", "f(1)=2",
        "--cond", "f'(0)=1"},
       "--cond: 3 conditions but form 1/0 has only 2 coefficients"},
      {"negative derivative order",
       {"rational", "--target", "exp", "--form", "1/0", "--cond", "f(0)=1", "--cond",
        "f^(-2)(0)=1"},
       "--cond:2:4: the derivative order must be 0 or more, not -2"},
      {"condition outside the domain",
       {"rational", "--target", "exp", "--domain", "0,1", "--form", "1/0", "--cond", "f(0)=1",
        "--cond", "f(1.5)=2"},
       "--cond:2:3: condition 'f(1.5)=2': the point 1.5 is outside the domain [0, 1]"},
      {"denominator vanishes in the domain",
       {"rational", "--target", "exp", "--domain", "0,1", "--form", "0/1", "--cond", "f(0)=1",
        "--cond", "f(1)=-1"},
       "--form:1:1: form 0/1: denominator 1 - 2 * x vanishes at x = 0.5 in the domain [0, 1]"},
      {"fewer conditions than coefficients",
       {"rational", "--target", "exp", "--form", "3/0", "--cond", "f(0)=1"},
       "form 3/0 has 4 coefficients but there is 1 condition"},
      {"nonlinear condition in a rational minimax",
       {"rational", "--target", "exp", "--form", "2/1", "--cond", "int(0,1)=ref", "--minimax"},
       "is not linear in the coefficients of form 2/1"},
      {"unknown target",
       {"rational", "--target", "fresnell", "--form", "1/0"},
       "--target: unknown target 'fresnell'"},
      {"formula syntax", {"rational", "--target", "x +* 2", "--form", "1/0"}, "--target:1:4"},
      {"unknown function",
       {"rational", "--target", "acoss(x)", "--form", "1/0"},
       "--target:1:1: unknown function 'acoss'"},
      {"domain of another variable",
       {"rational", "--target", "erf(x)", "--domain", "t=0:1", "--form", "1/0"},
       "--domain:1:1: the domain is of 't', but the variable is 'x'"},
      {"reversed domain",
       {"rational", "--target", "erf(x)", "--domain", "x=1:0", "--form", "1/0"},
       "--domain: the domain of 'x' is reversed"},
      {"function without a file",
       {"rational", "--function", "f", "--form", "1/0"},
       "--function: --function names a function of a shader source"},
      {"shader variable not determined",
       {"rational", "--reference-file",
        testing::scratch_file("two.hlsl",
                              "float f(float a, float b) {\n"
                              "  return a * b;\n}\n"),
        "--function", "f", "--form", "1/0"},
       "two.hlsl: f has the parameters a, b"},
      {"bad parameter",
       {"rational", "--target", "exp", "--param", "F0=0.1,y", "--form", "1/0"},
       "--param:1:8"},
      {"bad form",
       {"rational", "--target", "exp", "--form", "2/-1"},
       "--form:1:3: a degree must be 0 or more"},
      {"unknown name in a value",
       {"rational", "--target", "exp", "--form", "0/0", "--cond", "f(0)=F0"},
       "--cond:1:6: unknown name 'F0'"},
      {"missing target parameter",
       {"rational", "--target", "fresnel-schlick", "--form", "0/0", "--cond", "f(0)=1"},
       "needs a value for its parameter F0"},
      {"non-affine transform",
       {"rational", "--target", "exp", "--form", "1/0", "--transform", "x^2"},
       "must be affine"},
  };
  for (const BadInput& c : cases) {
    CliResult r = run(c.args);
    EXPECT_EQ(r.status, 2) << c.name << ": " << r.err << r.out;
    EXPECT_EQ(line_count(r.err), 1) << c.name << ": " << r.err;
    EXPECT_NE(r.err.find(c.expect), std::string::npos) << c.name << ": " << r.err;
  }
}

}  // namespace
}  // namespace shaderfit::cli
