// --uniform across the commands (cost/per_material.hpp): per-pixel and per-material costs, code
// in two parts, the search's per-pixel front, and each bad input as one line and status 2.
#include <gtest/gtest.h>

#include <cmath>
#include <iterator>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>

#include "cli_test_util.hpp"

namespace shaderfit::cli::testing {
namespace {

const char* const kBlinnPhong = "1/(3.14159*alpha^2) * pow(NoH, 2/alpha^2 - 2)";

// Beckmann's D over NoH in [0.1, 1] x alpha in [0.1, 0.5], where D >= 0.01.
std::string beckmann_csv() {
  std::ostringstream csv;
  csv << "NoH,alpha,D\n";
  for (int i = 0; i < 24; ++i) {
    for (int j = 0; j < 8; ++j) {
      const double c = 0.1 + 0.9 * i / 23, a = 0.1 + 0.4 * j / 7, c2 = c * c;
      const double d = std::exp((c2 - 1) / (a * a * c2)) / (3.141592653589793 * a * a * c2 * c2);
      if (d >= 0.01) csv << c << ',' << a << ',' << d << '\n';
    }
  }
  return scratch_file("beckmann.csv", csv.str());
}

TEST(CmdUniform, CostSplitsPerPixelAndPerMaterial) {
  const CliResult r = run({"cost", "--uniform", "alpha", kBlinnPhong});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(std::regex_search(r.out, std::regex("\\nsass +3 .* 6\\n"))) << r.out;
  EXPECT_NE(r.out.find("per pixel: exp2(m0 * log2(NoH) + m1)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("listing, per material:"), std::string::npos) << r.out;

  const CliResult j = run({"cost", "--uniform", "alpha", "--json", "-", kBlinnPhong});
  ASSERT_EQ(j.status, 0) << j.err;
  const auto doc = nlohmann::json::parse(j.out);
  EXPECT_EQ(doc["targets"]["sass"]["instructions"], 3);
  EXPECT_EQ(doc["targets"]["sass"]["per_material"]["instructions"], 6);
  EXPECT_EQ(doc["uniform"], nlohmann::json::array({"alpha"}));
  EXPECT_EQ(doc["material_values"].size(), 2u);
  // Without --uniform every instruction is per pixel.
  const auto all = nlohmann::json::parse(run({"cost", "--json", "-", kBlinnPhong}).out);
  EXPECT_EQ(all["targets"]["sass"]["instructions"], 9);
}

TEST(CmdUniform, CodegenPrintsTwoPartsWithBothCosts) {
  const CliResult r =
      run({"codegen", "--lang", "hlsl", "--name", "d", "--uniform", "alpha", kBlinnPhong});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("cost model: per pixel 3 SASS, 3 PTX, 4 generic, 3 RDNA; per material 6 SASS"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("struct d_material {"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("d_material d_material_values(float alpha) {"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("float d(float NoH, d_material m) {"), std::string::npos) << r.out;
}

TEST(CmdUniform, BadUniformInputsAreOneLineAndStatus2) {
  expect_bad_input({"cost", "--uniform", "beta", kBlinnPhong},
                   "--uniform: uniform input 'beta' is not an input (inputs: alpha, NoH)");
  expect_bad_input({"cost", "--uniform", "alpha,NoH", kBlinnPhong},
                   "--uniform: every input is uniform");
  expect_bad_input({"codegen", "--lang", "glsl", "--uniform", "alpha,alpha", kBlinnPhong},
                   "--uniform: uniform input 'alpha' is given twice");
  const std::string csv = beckmann_csv();
  expect_bad_input(
      {"search", "--data", csv, "--target", "D", "--uniform", "roughness", "--evals", "1000"},
      "--uniform: uniform input 'roughness' is not an input");
  expect_bad_input(
      {"search", "--data", csv, "--target", "D", "--uniform", "alpha,NoH", "--evals", "1000"},
      "--uniform: every input is uniform");
  expect_bad_input({"eval", "--data", csv, "--target", "D", "--uniform", "beta", kBlinnPhong},
                   "--uniform: uniform input 'beta' is not an input");
  // The search says so before anything else.
  const CliResult r =
      run({"search", "--data", csv, "--target", "D", "--uniform", "beta", "--evals", "1000"});
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.out, "");
}

TEST(CmdUniform, EvalChecksTheUniformInputIsConstantPerGroup) {
  // alpha varies within each NoH group: not a per-material input there.
  const std::string csv = beckmann_csv();
  expect_bad_input(
      {"eval", "--data", csv, "--target", "D", "--uniform", "alpha", "--group", "NoH", kBlinnPhong},
      "--uniform: uniform input 'alpha' varies within group NoH=");
  // Grouped by alpha itself it is constant per group, and each formula has both costs.
  const CliResult r = run({"eval", "--data", csv, "--target", "D", "--uniform", "alpha", "--group",
                           "alpha", kBlinnPhong});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("cost: 3 per pixel, 6 per material"), std::string::npos) << r.out;
  const auto j = nlohmann::json::parse(run({"eval", "--data", csv, "--target", "D", "--uniform",
                                            "alpha", "--json", "-", kBlinnPhong})
                                           .out);
  EXPECT_EQ(j["results"][0]["cost"]["per_pixel"], 3);
}

TEST(CmdUniform, SearchRanksPerPixelAndWritesBothCosts) {
  const std::string csv = beckmann_csv();
  const std::string json = scratch_file("uniform_search.json", "");
  const CliResult r =
      run({"search", "--data", csv, "--target", "D", "--uniform", "alpha", "--loss", "max_rel",
           "--evals", "200000", "--threads", "1", "--quiet", "--json", json});
  ASSERT_EQ(r.status, 0) << r.err;
  std::ifstream f(json);
  const auto doc = nlohmann::json::parse(f);
  EXPECT_EQ(doc["uniform"], nlohmann::json::array({"alpha"}));
  EXPECT_EQ(doc["options"]["uniform"], nlohmann::json::array({"alpha"}));
  // A member at per-pixel cost <= 3 beats Blinn-Phong's max_rel (1.5 on these rows).
  double best = INFINITY;
  for (const auto& m : doc["front"]) {
    ASSERT_TRUE(m.contains("material_cost")) << m.dump();
    if (m["cost"].get<double>() <= 3) best = std::min(best, m["max_rel"].get<double>());
  }
  const CliResult bp = run({"eval", "--data", csv, "--target", "D", "--json", "-", kBlinnPhong});
  const double published =
      nlohmann::json::parse(bp.out)["results"][0]["all"]["max_rel"].get<double>();
  EXPECT_LT(best, published);
  // The front's code is in two parts, and the report shows both costs.
  const CliResult code = run({"codegen", "--lang", "glsl", "--front", json});
  ASSERT_EQ(code.status, 0) << code.err;
  EXPECT_NE(code.out.find("_material_values(float alpha)"), std::string::npos) << code.out;
  const std::string html = scratch_file("uniform_report.html", "");
  const CliResult report = run({"report", json, "--output", html});
  ASSERT_EQ(report.status, 0) << report.err;
  std::ifstream page(html);
  const std::string text((std::istreambuf_iterator<char>(page)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("cost per pixel"), std::string::npos);
  EXPECT_NE(text.find("per material"), std::string::npos);
  EXPECT_NE(text.find("_material_values(float alpha)"), std::string::npos);
}

}  // namespace
}  // namespace shaderfit::cli::testing
