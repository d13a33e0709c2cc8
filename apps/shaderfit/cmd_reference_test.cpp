// Any function in, a verified formula out, through run_cli: a reference formula or a shader
// function sampled by shaderfit, the errors checked between the samples and certified, a CSV
// whose inputs and target are inferred, and each bad input as one clear line.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cli_test_util.hpp"
#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/expr/parse.hpp"

namespace shaderfit::cli {
namespace {

using testing::expect_bad_input;
using testing::run;
using testing::scratch_file;


// The largest |f(x) - acos(x)| over n uniform points of [-1, 1], f evaluated in double.
double acos_grid_max(const std::string& formula, int n) {
  ParseOptions po;
  po.variables = {"x"};
  const Expression e = parse_formula(formula, po);
  std::vector<double> x(static_cast<std::size_t>(n)), f(x.size());
  for (int i = 0; i < n; ++i) x[static_cast<std::size_t>(i)] = -1 + 2.0 * i / (n - 1);
  const double* columns[] = {x.data()};
  evaluate(e, columns, f, {.threads = 1});
  double worst = 0;
  for (std::size_t i = 0; i < x.size(); ++i)
    worst = std::max(worst, std::abs(f[i] - std::acos(x[i])));
  return worst;
}

TEST(CmdReference, SearchOnAFormulaChecksEveryMemberBetweenTheSamples) {
  const auto r =
      run({"search", "--reference", "acos(x)", "--domain", "x=-1:1", "--loss", "max_abs", "--ops",
           "auto", "--threads", "1", "--evals", "200000", "--quiet", "--json", "-"});
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["inputs"], nlohmann::json({"x"}));
  EXPECT_EQ(j["problem"]["reference"], "acos(x)");
  EXPECT_EQ(j["data"]["rows"], 10001);
  ASSERT_FALSE(j["front"].empty());
  for (const auto& m : j["front"]) {
    EXPECT_EQ(m["max_abs_checked"], "between samples") << m["formula"];
    // What shaderfit prints is never below the error on a grid 100 times finer than its samples.
    const double dense = acos_grid_max(m["formula"].get<std::string>(), 1000001);
    EXPECT_GE(m["max_abs"].get<double>(), dense * (1 - 1e-9)) << m["formula"];
    EXPECT_LE(m["max_abs"].get<double>(), dense * 1.01) << m["formula"];
    EXPECT_GT(m["float32_max_abs"].get<double>(), 0);
  }
}

TEST(CmdReference, CertifiedBoundsHoldAndAreMarked) {
  const auto r = run({"search", "--reference", "acos(x)", "--domain", "x=-1:1", "--loss", "max_abs",
                      "--threads", "1", "--evals", "20000", "--strategy", "enumerate", "--certify",
                      "--certify-time", "5", "--json", "-"});
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  for (const auto& m : j["front"]) {
    ASSERT_TRUE(m.contains("certified_max_abs")) << m;
    if (m["certified_max_abs"].is_null()) continue;  // no finite bound
    EXPECT_GE(m["certified_max_abs"].get<double>(), m["max_abs"].get<double>()) << m["formula"];
  }
  const auto table = run({"search", "--reference", "acos(x)", "--domain", "x=-1:1", "--loss",
                          "max_abs", "--threads", "1", "--evals", "20000", "--strategy",
                          "enumerate", "--certify", "--quiet"});
  ASSERT_EQ(table.status, 0) << table.err;
  EXPECT_NE(table.out.find("certified"), std::string::npos) << table.out;
  EXPECT_NE(table.out.find("f32 max_abs"), std::string::npos) << table.out;
}

// Smith GGX G1 as a user has it in a shader: locals, a ?:, a saturate.
constexpr const char* kSmithGlsl = R"(#version 450
// Smith GGX masking for one direction.
float G1(float NdotV, float roughness) {
  float a = roughness * roughness;
  float a2 = a * a;
  float NdotV2 = NdotV * NdotV;
  float denom = NdotV + sqrt(a2 + (1.0 - a2) * NdotV2);
  return NdotV > 0.0 ? saturate(2.0 * NdotV / denom) : 0.0;
}
)";

TEST(CmdReference, AShaderFunctionRunsThroughSearchCodegenAndReportWithNoCsv) {
  const std::string glsl = scratch_file("smith.glsl", kSmithGlsl);
  const std::string json = scratch_file("smith.json", "");
  const auto s = run({"search", "--reference-file", glsl, "--function", "G1", "--domain",
                      "NdotV=0:1", "--domain", "roughness=0.05:1", "--threads", "1", "--evals",
                      "100000", "--quiet", "--json", json});
  ASSERT_EQ(s.status, 0) << s.err;
  EXPECT_NE(s.out.find("inputs NdotV,roughness"), std::string::npos) << s.out;
  const auto c = run({"codegen", "--lang", "glsl", "--front", json});
  ASSERT_EQ(c.status, 0) << c.err;
  EXPECT_NE(c.out.find("float"), std::string::npos) << c.out;
  // The report samples the reference again from what the JSON recorded.
  const std::string html = scratch_file("smith.html", "");
  std::filesystem::remove(glsl);  // the JSON holds the function's text
  const auto rep = run({"report", json, "-o", html});
  ASSERT_EQ(rep.status, 0) << rep.err;
  std::ifstream f(html);
  const std::string page((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  EXPECT_NE(page.find("Against the baselines"), std::string::npos);
}

// A reference whose tree is too large for the search says so in one line, with its cost as
// written, and the search goes on from the samples.
TEST(CmdReference, AReferenceTooLargeAsATreeSaysItsCost) {
  const std::string hlsl = scratch_file("newton6.hlsl", R"(
float CbrtNewton(float v) {
  float y = 0.5 + 0.5 * v;
  [unroll] for (int it = 0; it < 6; ++it) { float y2 = y * y; y = (2.0 * y + v / y2) / 3.0; }
  return y;
})");
  const auto s = run({"search", "--reference-file", hlsl, "--function", "CbrtNewton", "--domain",
                      "v=0.1:8", "--threads", "1", "--evals", "20000", "--quiet"});
  ASSERT_EQ(s.status, 0) << s.err;
  EXPECT_NE(s.out.find("reference: not on the front as written: written out as a formula it has "
                       "more than 4096 nodes (it costs 31 instructions)"),
            std::string::npos)
      << s.out;
}

TEST(CmdReference, ACsvWithColumnsXAndYNeedsNoInputsOrTarget) {
  std::string csv = "x,y\n";
  for (int i = 0; i <= 64; ++i) {
    const double x = i / 64.0;
    csv += std::to_string(x) + "," + std::to_string(2.5 * std::sqrt(x + 0.5)) + "\n";
  }
  const auto r = run({"search", "--data", scratch_file("xy.csv", csv), "--time", "0.3",
                      "--strategy", "enumerate", "--threads", "1", "--quiet"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("inputs x, target y"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("operators (auto): "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("sqrt"), std::string::npos) << r.out;
}

TEST(CmdReference, EvalOnAReferenceChecksBetweenTheSamplesAndCertifies) {
  const auto r = run({"eval", "--reference", "acos(x)", "--domain", "x=0:1", "--certify",
                      "sqrt(1 - x)*(1.5707288 + x*(-0.2121144 + x*(0.0742610 - 0.0187293*x)))"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("searched for between the samples too"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("certified: |error| <= "), std::string::npos) << r.out;
}

TEST(CmdReference, BadInputsAreOneClearLine) {
  expect_bad_input({"search", "--reference", "acoss(x)", "--domain", "x=-1:1"},
                   "--reference:1:1: unknown function 'acoss'");
  expect_bad_input({"search", "--reference", "acos(x) + y", "--domain", "x=-1:1"},
                   "no domain for variable 'y'");
  expect_bad_input({"search", "--reference", "acos(x)", "--domain", "x=1:1"}, "--domain");
  expect_bad_input({"search", "--reference", "acos(x)", "--domain", "x=1:-1"}, "--domain");
  expect_bad_input({"search", "--reference", "acos(x)", "--domain", "x=-2:1"},
                   "the reference is NaN or infinite at");
  expect_bad_input(
      {"search", "--reference", "acos(x)", "--domain", "x=0:1", "--certify", "--certify-time", "0"},
      "--certify-time");
  const std::string loop = scratch_file("loop.glsl",
                                        "float f(float x) {\n"
                                        "  float s = 0.0;\n"
                                        "  while (s < 4.0) s += x;\n"
                                        "  return s;\n"
                                        "}\n");
  expect_bad_input({"search", "--reference-file", loop, "--function", "f", "--domain", "x=0:1"},
                   "loop.glsl:3:10: the condition of this while loop is not a constant");
  expect_bad_input({"search", "--data", scratch_file("one.csv", "x\n1\n2\n3\n")}, "one column");
  expect_bad_input({"eval", "--data", scratch_file("xy2.csv", "x,y\n1,2\n2,3\n"), "--certify", "x"},
                   "--certify");
}

// A CSV never loses a column silently: a gap in a column of numbers is an error at its cell,
// or its row is dropped with --drop-missing and counted; every command takes the data options.
TEST(CmdReference, CsvGapsAreErrorsOrDroppedRows) {
  std::string csv = "a,b,y\n";
  for (int i = 0; i < 40; ++i)
    csv += std::to_string(i) + "," + (i == 7 ? std::string() : std::to_string(0.5 * i)) + "," +
           std::to_string(i + 0.5 * i) + "\n";
  const std::string path = scratch_file("gaps.csv", csv);
  expect_bad_input({"search", "--data", path, "--evals", "2000"},
                   path + ":9:3: column 'b' is numbers but for 1 cell: this one is empty (fix "
                          "them, or drop their rows: --drop-missing)");
  expect_bad_input({"eval", "--data", path, "a + b"}, path + ":9:3:");
  const auto r = run({"search", "--data", path, "--drop-missing", "--evals", "2000",
                           "--threads", "1", "--quiet"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("dropped 1 of 40 rows with an empty or non-number cell in a column of "
                       "numbers, first at line 9"),
            std::string::npos)
      << r.out;
  const std::string word = scratch_file("word.csv", "a,b,y\n1,2,3\n4,five,6\n7,8,9\n");
  expect_bad_input({"search", "--data", word, "--evals", "2000"},
                   word + ":3:3: column 'b' is numbers but for 1 cell: this one is 'five'");
  expect_bad_input({"search", "--reference", "x", "--domain", "x=0:1", "--drop-missing"},
                   "--drop-missing: dropping rows with gaps is for a CSV file");
  expect_bad_input({"search", "--reference", "acos(x)", "--domain", "x=0:1", "--samples", "0"},
                   "--samples");
  // eval takes --inputs as search does; a formula reading another column is an error.
  const std::string xy = scratch_file("abxy.csv", "a,b,y\n1,2,3\n2,3,5\n3,5,8\n");
  const auto e = run({"eval", "--data", xy, "--inputs", "a,b", "--target", "y", "a + b"});
  ASSERT_EQ(e.status, 0) << e.err;
  expect_bad_input({"eval", "--data", xy, "--inputs", "a", "--target", "y", "a + b"},
                   "formula 1: it reads 'b', which is not one of the inputs given");
}

TEST(CmdReference, NaNPointsAreDroppedOnRequest) {
  const auto r = run({"search", "--reference", "acos(x)", "--domain", "x=-2:1", "--drop-nonfinite",
                      "--evals", "2000", "--threads", "1", "--quiet"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("dropped"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace shaderfit::cli
