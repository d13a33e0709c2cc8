#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "cli_test_util.hpp"
#include "shaderfit/lut/fv_lut.hpp"

namespace shaderfit::cli {
namespace {

using testing::CliResult;
using testing::line_count;
using testing::run;

const char* kShape = "r0 + (1 - r0 - s*cos_theta)*x^4";
const char* kSchlick = "r0 + (1 - r0)*x^5";
const char* kSeed = "r0 + (x - r0)*x^4";

// Seed 001's shape parameter: one s per material; for every metal the fitted form is no worse
// than Schlick and than the seed formula (s = 1 is in the family, so the second is by design).
TEST(CliFit, ShapeParameterPerMetalBeatsSchlickAndTheSeedFormula) {
  CliResult r = run({"fit", "--dataset", "fresnel-seed", "--seed", "1", "--target", "R", "--param",
                     "s=1", "--per-group", "s:material", "--baseline", kSchlick, "--baseline",
                     kSeed, kShape, "--json", "-"});
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_TRUE(j["linear"].get<bool>());
  int metals = 0;
  bool dielectric_range = false;
  for (const auto& b : j["blocks"]) {
    const std::string label = b["label"];
    dielectric_range = dielectric_range || label == "material=ior1.34-1.7";
    ASSERT_TRUE(b["ok"].get<bool>()) << label;
    if (label.find("metal") == std::string::npos) continue;
    ++metals;
    const double mse = b["mse"], schlick = b["baseline_mse"][0], seed = b["baseline_mse"][1];
    EXPECT_LE(mse, schlick) << label;
    EXPECT_LE(mse, seed) << label;
  }
  EXPECT_EQ(metals, 7);
  EXPECT_TRUE(dielectric_range);
}

TEST(CliFit, TableForPeople) {
  CliResult r = run({"fit", "--dataset", "fresnel-seed", "--target", "R", "--param", "s=1",
                     "--per-group", "s:material", "--baseline", kSchlick, kShape});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("material=metal 0.3+3i"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("MSE [1]"), std::string::npos);
  EXPECT_NE(r.out.find("linear least squares"), std::string::npos);
}

// The seed 002 problem through the generic command: a 4 x 4 grid of cells, per-cell A, B, C,
// the transform log2(y / f0), C = 0. It must give the lut's constrained table exactly.
TEST(CliFit, PerCellTransformAndConstraintMatchTheLut) {
  CliResult r = run({"fit",
                     "--domain",
                     "theta=0:pi/2:45",
                     "--grid",
                     "roughness=0:1:4",
                     "--grid",
                     "f0=0:1:4:sqrt",
                     "--define",
                     "dot_lh = cos(theta)",
                     "--define",
                     "x = 1 - dot_lh",
                     "--reference",
                     "fv-schlick-smith-lh",
                     "--transform",
                     "log2(y / f0)",
                     "--param",
                     "A,B,C",
                     "--per-cell",
                     "A,B,C",
                     "--constraint",
                     "C = 0",
                     "f0 * exp2(A*x^2 + B*x + C)",
                     "--json",
                     "-"});
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_TRUE(j["linear"].get<bool>());
  ASSERT_EQ(j["blocks"].size(), 16u);
  lut::FvLutOptions o;
  o.size = 4;
  o.fit_samples = 45;
  o.eval_samples = 10;
  o.endpoint_grid = 4;
  const std::array<lut::FvVariant, 1> v = {lut::FvVariant::constrained};
  const lut::FvBake bake = lut::bake_fv_luts(o, v);
  for (std::size_t k = 0; k < 16; ++k) {
    const auto& p = j["blocks"][k]["parameters"];
    // Cells run over roughness (first axis) then f0; the lut's rows are f0.
    const lut::FvCell& c = bake.tables[0].cells[(k % 4) * 4 + k / 4];
    EXPECT_EQ(p["C"].get<double>(), 0.0);
    EXPECT_NEAR(p["A"].get<double>(), c.a, 1e-9 * (1 + std::abs(c.a)));
    EXPECT_NEAR(p["B"].get<double>(), c.b, 1e-9 * (1 + std::abs(c.b)));
  }
}

TEST(CliFit, GlobalAndPerGroupTogetherAndConstraints) {
  CliResult r =
      run({"fit", "--dataset", "fresnel-seed", "--target", "R", "--param", "s=1,k", "--per-group",
           "s:material", "--constraint", "f(x = 1, cos_theta = 0, r0 = 0.04) = 1",
           "r0 + (1 - r0 - s*cos_theta)*x^4 + k*x^5", "--json", "-"});
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_TRUE(j["coupled"].get<bool>());
  // The value at grazing incidence is 1 + k in every block: the joint solve keeps k = 0.
  for (const auto& b : j["blocks"]) EXPECT_NEAR(b["parameters"]["k"].get<double>(), 0.0, 1e-12);
}

struct BadInput {
  const char* name;
  std::vector<std::string> args;
  const char* expected;
};

void PrintTo(const BadInput& b, std::ostream* os) { *os << b.name; }

class CliFitErrors : public ::testing::TestWithParam<BadInput> {};

TEST_P(CliFitErrors, OneClearLineAndStatus2) {
  const BadInput& b = GetParam();
  std::vector<std::string> args = {"fit", "--dataset", "fresnel-seed", "--target", "R"};
  args.insert(args.end(), b.args.begin(), b.args.end());
  CliResult r = run(args);
  EXPECT_EQ(r.status, 2) << r.out << r.err;
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_EQ(r.err.rfind("shaderfit: error: ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find(b.expected), std::string::npos) << "stderr: " << r.err;
}

INSTANTIATE_TEST_SUITE_P(
    All, CliFitErrors,
    ::testing::Values(
        BadInput{"no_free_parameters",
                 {"r0 + (1 - r0)*x^5"},
                 "formula: the formula 'r0 + (1 - r0) * x^5' has no free parameters"},
        BadInput{"contradicting_constraints",
                 {"--param", "a,b", "--constraint", "a = 0", "--constraint", "a = 1", "a + b*x"},
                 "constraint 'a = 1' contradicts 'a = 0'"},
        BadInput{"singular",
                 {"--param", "a,b", "a*x + b*x"},
                 "singular system: the data and constraints do not determine parameter"},
        BadInput{"negative_weight", {"--param", "a", "--weight", "x - 0.5", "a*x"}, "is negative"},
        BadInput{"grid_size_zero",
                 {"--param", "a", "--per-cell", "a", "--grid", "r0=0:1:0", "a*x"},
                 "--grid: grid size must be at least 1, got 0"},
        BadInput{"parameter_not_in_formula",
                 {"--param", "a,b", "a*x"},
                 "parameter 'b' does not appear in the formula"},
        BadInput{"per_cell_without_grid",
                 {"--param", "a", "--per-cell", "a", "a*x"},
                 "--per-cell needs a grid"},
        BadInput{"unknown_loss", {"--param", "a", "--loss", "l1", "a*x"}, "unknown loss 'l1'"},
        BadInput{"constraint_syntax",
                 {"--param", "a", "--constraint", "a + ", "a*x"},
                 "--constraint 1:1:"},
        BadInput{"linear_solver_on_nonlinear",
                 {"--param", "a", "--solver", "linear", "exp(a*x)"},
                 "not linear"},
        BadInput{"formula_outside_the_inputs",
                 {"--param", "a", "--inputs", "x", "a*r0"},
                 "--inputs: the formula reads 'r0', which is not among the inputs (x)"},
        BadInput{"input_no_column",
                 {"--param", "a", "--inputs", "x,zz", "a*x"},
                 "--inputs: input 'zz' is no column"}),
    [](const ::testing::TestParamInfo<BadInput>& p) { return std::string(p.param.name); });

// A reference that is NaN or infinite at some points: an error naming the first, or with
// --drop-nonfinite those points left out and counted.
TEST(CliFit, NonFiniteReferenceIsAnErrorOrLeftOut) {
  const std::vector<std::string> args = {"fit",     "--domain", "x=-1:1:5", "--reference",
                                         "sqrt(x)", "--param",  "a,b",      "a + b*x"};
  CliResult r = run(args);
  EXPECT_EQ(r.status, 2) << r.out << r.err;
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("--reference: the reference is NaN or infinite at sampled point 1 (2 "
                       "such; leave them out: --drop-nonfinite)"),
            std::string::npos)
      << r.err;
  std::vector<std::string> dropping = args;
  dropping.push_back("--drop-nonfinite");
  r = run(dropping);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("2 rows where the reference is NaN or infinite were left out"),
            std::string::npos)
      << r.out;
}

// The reference language: a formula of functions a built-in does not cover, on a domain sampled
// by the default design (no count), with definitions in the same language.
TEST(CliFit, ReferenceLanguageOnTheDefaultDesign) {
  // Abramowitz and Stegun 4.4.45's form: acos(x) ~ sqrt(1 - x) (a + b x + c x^2 + d x^3).
  CliResult r =
      run({"fit", "--domain", "x=0:1", "--define", "s = sqrt(1 - x)", "--reference", "acos(x)",
           "--param", "a,b,c,d", "--loss", "max", "s*(a + b*x + c*x^2 + d*x^3)", "--json", "-"});
  ASSERT_EQ(r.status, 0) << r.err;
  auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["reference"], "acos(x)");
  ASSERT_EQ(j["blocks"].size(), 1u);
  EXPECT_EQ(j["blocks"][0]["rows"].get<int>(), 10001);
  EXPECT_TRUE(j["linear"].get<bool>());
  // A&S's own constants (a = 1.5707288, ...) err by 6.75e-5; the minimax fit is no worse.
  EXPECT_LT(j["blocks"][0]["max_abs"].get<double>(), 6.75e-5);
  EXPECT_NEAR(j["blocks"][0]["parameters"]["a"].get<double>(), 1.5707288, 1e-4);
  // --samples sizes the design; erf and atan2 are references' functions.
  r = run({"fit", "--domain", "x=0:3", "--samples", "257", "--reference", "erf(x) * atan2(1, x)",
           "--param", "a,b", "a*x/(1 + b*x)", "--json", "-"});
  ASSERT_EQ(r.status, 0) << r.err;
  j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["blocks"][0]["rows"].get<int>(), 257);
  EXPECT_TRUE(j["blocks"][0]["ok"].get<bool>());
}

// A GLSL function as the reference: its parameters are the sampled variables.
TEST(CliFit, ReferenceFileAndFunction) {
  const std::string glsl =
      testing::scratch_file("g1.glsl",
                            "float G1(float NdotV, float roughness) {\n"
                            "  float a = roughness * roughness;\n"
                            "  float d = NdotV + sqrt(a * a + (1.0 - a * a) * NdotV * NdotV);\n"
                            "  return d > 1e-4 ? 2.0 * NdotV / d : 0.0;\n"
                            "}\n");
  CliResult r = run({"fit", "--domain", "NdotV=0:1:64", "--grid", "roughness=0.1:1:3",
                     "--reference-file", glsl, "--function", "G1", "--param", "k=0.5", "--per-cell",
                     "k", "NdotV / (NdotV*(1 - k) + k)", "--json", "-"});
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_NE(j["reference"].get<std::string>().find("g1.glsl: G1"), std::string::npos);
  ASSERT_EQ(j["blocks"].size(), 3u);
  double last = 0;
  for (const auto& b : j["blocks"]) {
    ASSERT_TRUE(b["ok"].get<bool>());
    const double k = b["parameters"]["k"];
    EXPECT_GT(k, last);  // rougher: more shadowing, a larger k
    last = k;
  }
  const CliResult bad = run({"fit", "--domain", "x=0:1", "--reference-file", glsl, "--function",
                             "G1", "--param", "k", "k*x"});
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("--function: the parameter 'NdotV' of "), std::string::npos) << bad.err;
}

TEST(CliFit, ReferenceLanguageErrorsAreLocated) {
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"--domain", "x=0:1", "--reference", "acoss(x)"},
       "--reference:1:1: unknown function 'acoss'"},
      {{"--domain", "x=0:1", "--define", "c = cos(x)", "--define", "d = erf(q)", "--reference",
        "d"},
       "--define:2:"},
      {{"--domain", "x=1:0", "--reference", "x"}, "--domain:1: the domain of 'x' is reversed"},
      {{"--domain", "x=0:1:8", "--samples", "100", "--reference", "x"}, "--samples:"},
      {{"--domain", "x=0:1", "--function", "f", "--reference", "x"},
       "--function: --function names a function of --reference-file"},
  };
  for (const auto& [args, expected] : cases) {
    std::vector<std::string> all = {"fit"};
    all.insert(all.end(), args.begin(), args.end());
    all.insert(all.end(), {"--param", "a", "a*x"});
    CliResult r = run(all);
    EXPECT_EQ(r.status, 2) << expected;
    EXPECT_EQ(line_count(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(expected), std::string::npos) << r.err;
  }
}

TEST(CliFit, UnknownReferenceAndHelp) {
  CliResult r =
      run({"fit", "--domain", "d=0:1:8", "--reference", "fv-exat", "--param", "a", "a*d"});
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("unknown reference 'fv-exat'"), std::string::npos) << r.err;
  CliResult h = run({"fit", "--help"});
  EXPECT_EQ(h.status, 0);
  EXPECT_NE(h.out.find("--per-group"), std::string::npos);
}

}  // namespace
}  // namespace shaderfit::cli
