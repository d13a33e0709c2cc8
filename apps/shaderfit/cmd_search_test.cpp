// shaderfit search through run_cli, in-process: the seed task, JSON output, and bad input.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "cli_test_util.hpp"

namespace shaderfit::cli {
namespace {

using testing::run;
using testing::scratch_file;

void expect_bad_input(const std::vector<std::string>& args, const std::string& text) {
  const auto r = run(args);
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find(text), std::string::npos) << r.err;
  EXPECT_EQ(testing::line_count(r.err), 1) << r.err;
}

TEST(CmdSearch, SeedTaskFindsTheSeedFormulaAndWritesJson) {
  const auto r = run({"search", "--dataset", "fresnel-seed", "--inputs", "r0,x", "--target", "R",
                      "--time", "60", "--strategy", "enumerate", "--stop-loss", "0.00035236",
                      "--stop-cost", "4", "--json", "-"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("] mse="), std::string::npos);  // members as found, on stderr with --json -
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_TRUE(j.contains("front"));
  bool met = false;
  for (const auto& m : j["front"]) {
    ASSERT_TRUE(m["formula"].is_string());
    ASSERT_TRUE(m["cost"].is_number());
    ASSERT_TRUE(m["mse"].is_number());
    ASSERT_TRUE(m["time_s"].is_number());
    met = met || (m["cost"].get<double>() <= 4 && m["mse"].get<double>() <= 0.00035236);
  }
  EXPECT_TRUE(met) << r.out;
  EXPECT_EQ(j["summary"]["termination"], "target reached");
  EXPECT_EQ(j["inputs"], nlohmann::json({"r0", "x"}));
}

TEST(CmdSearch, TableForPeople) {
  const auto r =
      run({"search", "--dataset", "fresnel-seed", "--time", "0.2", "--strategy", "enumerate"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("formula"), std::string::npos);
  EXPECT_NE(r.out.find("] mse="), std::string::npos);
  EXPECT_NE(r.out.find("r0"), std::string::npos);
}

TEST(CmdSearch, UnknownOperator) {
  expect_bad_input({"search", "--dataset", "fresnel-seed", "--ops", "+,*,frob"},
                   "unknown operator 'frob'");
}

TEST(CmdSearch, VariableNotInTheData) {
  expect_bad_input({"search", "--dataset", "fresnel-seed", "--inputs", "r0,theta"},
                   "no column 'theta'");
}

TEST(CmdSearch, TargetColumnMissing) {
  const std::string csv = scratch_file("search_no_target.csv", "x,y\n1,2\n2,3\n3,4\n");
  expect_bad_input({"search", "--data", csv, "--inputs", "x", "--target", "R"}, "no column 'R'");
}

TEST(CmdSearch, ZeroOrNegativeBudget) {
  expect_bad_input({"search", "--dataset", "fresnel-seed", "--time", "0"},
                   "time budget must be positive");
  expect_bad_input({"search", "--dataset", "fresnel-seed", "--time", "-3"},
                   "time budget must be positive");
  expect_bad_input({"search", "--dataset", "fresnel-seed", "--evals", "0"},
                   "evaluation budget must be positive");
  expect_bad_input({"search", "--dataset", "fresnel-seed", "--evals", "-5"},
                   "evaluation budget must be positive");
}

TEST(CmdSearch, DataSetWithOneRow) {
  const std::string csv = scratch_file("search_one_row.csv", "x,y\n1,2\n");
  expect_bad_input({"search", "--data", csv, "--inputs", "x", "--target", "y"}, "1 row");
}

TEST(CmdSearch, OtherBadOptions) {
  expect_bad_input({"search", "--dataset", "fresnel-seed", "--loss", "l7"}, "unknown loss 'l7'");
  expect_bad_input({"search", "--dataset", "fresnel-seed", "--cost", "watts"},
                   "unknown cost 'watts'");
  expect_bad_input({"search", "--dataset", "fresnel-seed", "--literals", "1,two"},
                   "not a number: 'two'");
}

}  // namespace
}  // namespace shaderfit::cli
