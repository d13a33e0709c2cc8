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

TEST(CmdCost, HalfRowIsPerTwoValuesAndLeftOutWhereThereIsNoHalfForm) {
  const CliResult r = run({"cost", "r0 + (1 - r0) * (1 - cos_theta)^5"});
  ASSERT_EQ(r.status, 0) << r.err;
  // docs/precision.md: Schlick is 7 instructions per __half2 call (two values).
  EXPECT_TRUE(std::regex_search(r.out, std::regex("\\nsass-half2 +7 "))) << r.out;
  const CliResult s = run({"cost", "sign(x) * x"});
  ASSERT_EQ(s.status, 0) << s.err;
  EXPECT_EQ(s.out.find("sass-half2"), std::string::npos) << s.out;
  const CliResult h = run({"cost", "--target", "sass-half2", "sign(x) * x"});
  EXPECT_EQ(h.status, 2);
  EXPECT_NE(h.err.find("sign has no half form"), std::string::npos) << h.err;
}

TEST(CmdCost, UnknownTargetIsOneLineAndStatus2) {
  const CliResult r = run({"cost", "--target", "x86", "a + b"});
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(line_count(r.err), 1);
  EXPECT_NE(r.err.find("unknown target 'x86'"), std::string::npos) << r.err;
}

TEST(CmdCost, BadFormulaIsOneLineAndStatus2) {
  const CliResult r = run({"cost", "a + * b"});
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(line_count(r.err), 1);
  EXPECT_NE(r.err.find("formula:1:"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace shaderfit::cli::testing
