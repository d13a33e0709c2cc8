// Scenes, the display loss and half precision on the command line (docs/scenes.md,
// docs/precision.md): what runs, and each bad input as one line and status 2.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cli_test_util.hpp"

namespace shaderfit::cli::testing {
namespace {

TEST(CmdScene, SearchWithTheDisplayLossAndItsReport) {
  const std::string json = scratch_file("scene.json", "");
  const CliResult r = run({"search", "--scene", "sphere", "--scene-size", "32", "--reference",
                           "fresnel-dielectric-f0", "--loss", "display", "--time", "1", "--threads",
                           "1", "--quiet", "--json", json});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("loss display"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("in the sphere scene"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("mean FLIP"), std::string::npos) << r.out;
  std::ifstream in(json);
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_EQ(j["problem"]["scene"]["kind"], "sphere");
  EXPECT_EQ(j["problem"]["scene"]["term"], "F");
  EXPECT_EQ(j["options"]["loss"], "display");

  const std::string html = scratch_file("scene.html", "");
  const CliResult rep =
      run({"report", json, "-o", html, "--baseline", "Schlick=f0 + (1 - f0)*(1 - v_dot_h)^5"});
  ASSERT_EQ(rep.status, 0) << rep.err;
  std::ifstream page(html);
  const std::string text((std::istreambuf_iterator<char>(page)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("In the picture"), std::string::npos);
  EXPECT_NE(text.find("Schlick: top to bottom: reference, approximation, FLIP map"),
            std::string::npos);
  EXPECT_NE(text.find("mean FLIP"), std::string::npos);
}

TEST(CmdScene, PlotSphereDrawsAnyFormulaOfTheQuantities) {
  const std::string png = scratch_file("fv.png", "");
  const CliResult r =
      run({"plot", "sphere", "--scene-size", "32", "--reference", "fv-exact", "--formula",
           "f0 * exp2(-5*(1 - l_dot_h)) * n_dot_l / n_dot_l", "-o", png});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("mean FLIP"), std::string::npos) << r.out;
  EXPECT_GT(std::filesystem::file_size(png), 100u);
}

TEST(CmdScene, BadInputs) {
  expect_bad_input({"search", "--scene", "teapot", "--reference", "fresnel-dielectric-f0"},
                   "--scene: unknown scene 'teapot' (known: sphere, plane)");
  expect_bad_input(
      {"search", "--scene", "sphere", "--reference", "fresnel-dielectric-f0", "--term", "G"},
      "--term: unknown term 'G'");
  // A formula input the scene does not provide.
  expect_bad_input({"search", "--scene", "sphere", "--term", "F", "--reference",
                    "fresnel_dielectric(cos_theta, 1.5)"},
                   "scene has no quantity 'cos_theta'");
  // A scene quantity the reference does not use.
  expect_bad_input({"search", "--scene", "sphere", "--reference", "fresnel-dielectric-f0",
                    "--inputs", "v_dot_h,n_dot_l"},
                   "input 'n_dot_l' is a scene quantity the reference does not use");
  expect_bad_input({"search", "--scene", "sphere", "--reference", "acos(n_dot_v)"},
                   "--term: which factor of the specular term");
  expect_bad_input({"search", "--reference", "x^2", "--domain", "x=0:1", "--loss", "display"},
                   "--loss: the display loss needs a scene");
  expect_bad_input(
      {"search", "--scene", "sphere", "--reference", "fresnel-dielectric-f0", "--domain", "x=0:1"},
      "--domain: a scene supplies the reference's inputs");
  expect_bad_input({"search", "--reference", "x^2", "--domain", "x=0:1", "--term", "F"},
                   "--scene: --term, --scene-size and --exposure are for a scene");
  expect_bad_input({"plot", "sphere", "--formula", "f0", "-o", "x.png"},
                   "--reference: --formula needs the function it approximates");
  expect_bad_input(
      {"plot", "sphere", "--reference", "fv-exact", "--formula", "f0 * q", "-o", "x.png"},
      "--formula:1:6: unknown variable 'q'");
}

TEST(CmdPrecision, HalfOverflowInTheReferenceSaysWhere) {
  expect_bad_input({"search", "--reference", "1e5 * x", "--domain", "x=0:1:11", "--precision",
                    "half", "--time", "1"},
                   "--precision: the target overflows half precision: 68181.81818181818 in row 8");
  expect_bad_input(
      {"eval", "--reference", "1e5 * x", "--domain", "x=0:1:11", "--precision", "half", "x"},
      "--precision: the target overflows half precision: 68181.81818181818 in row 8");
  expect_bad_input({"eval", "--dataset", "fresnel-seed", "--precision", "quarter", "x"},
                   "--precision: unknown precision 'quarter'");
  expect_bad_input({"search", "--dataset", "fresnel-seed", "--precision", "quarter"},
                   "--precision");
}

TEST(CmdPrecision, EvalInHalfShowsRounding) {
  const CliResult d = run(
      {"eval", "--dataset", "fresnel-seed", "--target", "R", "--json", "-", "r0 + (x - r0)*x^4"});
  const CliResult h = run({"eval", "--dataset", "fresnel-seed", "--target", "R", "--precision",
                           "half", "--json", "-", "r0 + (x - r0)*x^4"});
  ASSERT_EQ(d.status, 0) << d.err;
  ASSERT_EQ(h.status, 0) << h.err;
  const auto jd = nlohmann::json::parse(d.out), jh = nlohmann::json::parse(h.out);
  EXPECT_EQ(jh["precision"], "float16");
  const double dm = jd["results"][0]["all"]["max_abs"], hm = jh["results"][0]["all"]["max_abs"];
  EXPECT_NE(hm, dm);                   // half rounding changes the error ...
  EXPECT_LT(std::abs(hm - dm), 2e-3);  // ... by a few half ulps of values below 1
}

}  // namespace
}  // namespace shaderfit::cli::testing
