#include <gtest/gtest.h>

#include <cstdio>
#include <nlohmann/json.hpp>

#include "cli_test_util.hpp"

namespace shaderfit::cli {
namespace {

using testing::CliResult;
using testing::line_count;
using testing::run;
using testing::scratch_file;

const char* kSchlick = "r0 + (1 - r0)*x^5";
const char* kSeed = "r0 + (x - r0)*x^4";

TEST(CliEval, SeedClaimOnTheSeedDataSet) {
  CliResult r = run({"eval", "--dataset", "fresnel-seed", "--seed", "1", "--target", "R", "--baseline",
                     kSchlick, kSeed, "--json", "-"});
  ASSERT_EQ(r.status, 0) << r.err;
  auto j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["results"].size(), 2u);
  const auto& seed = j["results"][1];
  const double overall = seed["all"]["change_vs_baseline"]["mse"];
  const double metal = seed["groups"]["kind"]["metal"]["change_vs_baseline"]["mse"];
  const double dielectric = seed["groups"]["kind"]["dielectric"]["change_vs_baseline"]["mse"];
  // Seed 001: about 34% less MSE overall, almost 50% less for metals, dielectrics about equal.
  EXPECT_NEAR(overall, -0.34, 0.06);
  EXPECT_NEAR(metal, -0.50, 0.08);
  EXPECT_NEAR(dielectric, 0.0, 0.10);
  // Every metal of the seed's list is a group of its own.
  EXPECT_GE(seed["groups"]["material"].size(), 7u);
}

// --cost-target: each formula's count on that target, in the table and the JSON.
TEST(CliEval, CostTarget) {
  const CliResult r = run({"eval", "--dataset", "fresnel-seed", "--cost-target", "rdna2", kSeed});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("cost: 4 instructions (rdna2)"), std::string::npos) << r.out;
  const CliResult j = run({"eval", "--dataset", "fresnel-seed", "--cost-target", "sass", "--json", "-", kSchlick});
  ASSERT_EQ(j.status, 0) << j.err;
  const auto doc = nlohmann::json::parse(j.out);
  EXPECT_EQ(doc["results"][0]["cost"], nlohmann::json({{"target", "sass"}, {"instructions", 5}}));
  testing::expect_bad_input({"eval", "--dataset", "fresnel-seed", "--cost-target", "gcn", kSeed},
                            "--cost-target: unknown target 'gcn'");
}

// Constants for people: float32's shortest text, or --digits N significant digits; the JSON
// keeps the formula exact.
TEST(CliEval, DigitsOfTheConstants) {
  const char* f = "r0 + (x - r0) * x^4 * 0.98765432101234";
  CliResult r = run({"eval", "--dataset", "fresnel-seed", "--target", "R", f});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("[1] r0 + 0.9876543 * (x - r0) * x^4\n"), std::string::npos) << r.out;
  r = run({"eval", "--dataset", "fresnel-seed", "--target", "R", "--digits", "3", f});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("[1] r0 + 0.988 * (x - r0) * x^4\n"), std::string::npos) << r.out;
  r = run({"eval", "--dataset", "fresnel-seed", "--target", "R", "--json", "-", f});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("0.98765432101234"), std::string::npos);
  r = run({"eval", "--dataset", "fresnel-seed", "--target", "R", "--digits", "-1", f});
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("shaderfit: error: --digits: significant digits must be 1 to 17"),
            std::string::npos)
      << r.err;
}

TEST(CliEval, TableForPeople) {
  CliResult r = run({"eval", "--dataset", "fresnel-seed", "--target", "R", "--baseline", kSchlick, kSeed});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("[baseline] r0 + (1 - r0) * x^5"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("[1] r0 + (x - r0) * x^4"), std::string::npos);
  EXPECT_NE(r.out.find("kind=metal"), std::string::npos);
  EXPECT_NE(r.out.find("MSE vs baseline"), std::string::npos);
}

TEST(CliEval, CsvWithGroupsAndFloat32) {
  std::string path = scratch_file("small.csv", "a,b,g\n1,2,u\n2,4,v\n3,6.5,u\n");
  CliResult r = run({"eval", "--data", path, "--target", "b", "--group", "g", "2*a", "--float32", "--json", "-"});
  ASSERT_EQ(r.status, 0) << r.err;
  auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["precision"], "float32");
  EXPECT_DOUBLE_EQ(j["results"][0]["groups"]["g"]["u"]["mse"].get<double>(), 0.125);
  EXPECT_DOUBLE_EQ(j["results"][0]["groups"]["g"]["v"]["mse"].get<double>(), 0.0);
}

// One bad input each: exit status 2, one line on stderr naming the problem and its place.
struct BadInput {
  const char* name;
  std::vector<std::string> args;
  const char* csv;  // contents of bad.csv, or nullptr
  const char* expected;
};

void PrintTo(const BadInput& b, std::ostream* os) { *os << b.name; }

class CliEvalErrors : public ::testing::TestWithParam<BadInput> {};

TEST_P(CliEvalErrors, OneClearLineAndStatus2) {
  const BadInput& b = GetParam();
  std::vector<std::string> args = b.args;
  if (b.csv) {
    std::string path = scratch_file(std::string(b.name) + ".csv", b.csv);
    for (auto& a : args)
      if (a == "@csv") a = path;
  }
  CliResult r = run(args);
  EXPECT_EQ(r.status, 2) << r.out << r.err;
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_EQ(r.err.rfind("shaderfit: error: ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find(b.expected), std::string::npos) << "stderr: " << r.err;
}

const std::vector<std::string> kEvalCsv = {"eval", "--data", "@csv", "--target", "R", "r0 * x"};

INSTANTIATE_TEST_SUITE_P(
    All, CliEvalErrors,
    ::testing::Values(
        BadInput{"syntax", {"eval", "--dataset", "fresnel-seed", "--target", "R", "r0 + (x - r0"}, nullptr,
                 "formula 1:1:13: expected ')'"},
        BadInput{"baseline_syntax", {"eval", "--dataset", "fresnel-seed", "--target", "R", "--baseline", "r0 +* x", "x"},
                 nullptr, "--baseline:1:5:"},
        BadInput{"unknown_variable", {"eval", "--dataset", "fresnel-seed", "--target", "R", "r0 + y"}, nullptr,
                 "formula 1:1:6: unknown variable 'y'"},
        BadInput{"missing_column", kEvalCsv, "r0,x\n0.04,0.5\n", "no column 'R'"},
        BadInput{"non_number", kEvalCsv, "r0,x,R\n0.04,0.5,0.1\n0.04,abc,0.2\n", ":3:6: column 'x' is numbers but for 1 cell: this one is 'abc'"},
        BadInput{"ragged", kEvalCsv, "r0,x,R\n0.04,0.5,0.1\n0.04,0.5\n", ":3:"},
        BadInput{"nan", kEvalCsv, "r0,x,R\n0.04,0.5,nan\n", ":2:10: NaN"},
        BadInput{"inf", kEvalCsv, "r0,x,R\n0.04,inf,0.3\n", ":2:6:"},
        BadInput{"empty", kEvalCsv, "", "empty file"},
        BadInput{"missing_file", {"eval", "--data", "/nonexistent/dir/none.csv", "--target", "R", "x"}, nullptr,
                 "cannot open '/nonexistent/dir/none.csv'"},
        BadInput{"unknown_dataset", {"eval", "--dataset", "nope", "--target", "R", "x"}, nullptr,
                 "unknown data set 'nope'"},
        BadInput{"no_data", {"eval", "--target", "R", "x"}, nullptr, "no data"},
        BadInput{"unknown_group", {"eval", "--dataset", "fresnel-seed", "--target", "R", "--group", "colour", "x"},
                 nullptr, "no column 'colour'"},
        BadInput{"text_target", {"eval", "--dataset", "fresnel-seed", "--target", "material", "x"}, nullptr,
                 "column 'material' of fresnel-seed is text, not numbers"},
        BadInput{"unknown_option", {"eval", "--dataset", "fresnel-seed", "--target", "R", "--bogus", "x"}, nullptr,
                 "--bogus"}),
    [](const ::testing::TestParamInfo<BadInput>& p) { return std::string(p.param.name); });

TEST(CliEval, ProcessExitStatusAndHelp) {
  // The real binary: status 2 and one line for bad input; --help succeeds.
  const std::string cli = SHADERFIT_CLI_PATH;
  FILE* p = popen((cli + " eval --dataset fresnel-seed --target R 'x +' 2>&1").c_str(), "r");
  ASSERT_NE(p, nullptr);
  std::string text;
  char buf[512];
  while (fgets(buf, sizeof buf, p)) text += buf;
  const int status = pclose(p);
  EXPECT_EQ(WEXITSTATUS(status), 2);
  EXPECT_EQ(line_count(text), 1) << text;
  CliResult h = run({"eval", "--help"});
  EXPECT_EQ(h.status, 0);
  EXPECT_NE(h.out.find("--baseline"), std::string::npos) << h.out;
}

}  // namespace
}  // namespace shaderfit::cli
