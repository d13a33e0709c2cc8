#include <gtest/gtest.h>

#include <filesystem>

#include "cli_test_util.hpp"

namespace shaderfit::cli {
namespace {

using testing::CliResult;
using testing::line_count;
using testing::run;

const std::vector<std::string> kSmall = {"--size",         "8",  "--fit-samples",   "30",
                                         "--eval-samples", "30", "--endpoint-grid", "8"};

std::vector<std::string> lut(std::vector<std::string> extra) {
  std::vector<std::string> a = {"lut"};
  a.insert(a.end(), kSmall.begin(), kSmall.end());
  a.insert(a.end(), extra.begin(), extra.end());
  return a;
}

TEST(CliLut, BakesFourVariantsAndWritesTheFiles) {
  const auto dir = std::filesystem::temp_directory_path() / "shaderfit_cli_lut";
  std::filesystem::remove_all(dir);
  CliResult r = run(lut({"--out", dir.string()}));
  ASSERT_EQ(r.status, 0) << r.err;
  for (const char* v : {"endpoint", "linear", "constrained", "clamped"}) {
    EXPECT_NE(r.out.find(std::string("  ") + v), std::string::npos) << r.out;
    for (const char* suffix :
         {"_rgba32f.dds", "_rgba16f.dds", ".exr", "_errors.csv", "_errors.png"})
      EXPECT_TRUE(std::filesystem::exists(dir / (std::string("fv_") + v + suffix))) << v << suffix;
  }
  for (const char* f : {"fv_lut.hlsl", "fv_lut.glsl", "fv_summary.json"})
    EXPECT_TRUE(std::filesystem::exists(dir / f));
  EXPECT_NE(r.out.find("baked 4 tables in"), std::string::npos);
  EXPECT_TRUE(r.err.empty()) << r.err;
}

TEST(CliLut, ComparesWithTheExactReference) {
  CliResult r =
      run(lut({"--variant", "constrained", "--no-files", "--compare-exact", "constrained"}));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("dielectrics (grid)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("metal 2.9+3.1i"), std::string::npos);
}

struct BadInput {
  const char* name;
  std::vector<std::string> args;
  const char* expected;
};

void PrintTo(const BadInput& b, std::ostream* os) { *os << b.name; }

class CliLutErrors : public ::testing::TestWithParam<BadInput> {};

TEST_P(CliLutErrors, OneClearLineAndStatus2) {
  const BadInput& b = GetParam();
  std::vector<std::string> args = {"lut", "--no-files"};
  args.insert(args.end(), b.args.begin(), b.args.end());
  CliResult r = run(args);
  EXPECT_EQ(r.status, 2) << r.out << r.err;
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find(b.expected), std::string::npos) << "stderr: " << r.err;
}

INSTANTIATE_TEST_SUITE_P(
    All, CliLutErrors,
    ::testing::Values(
        BadInput{
            "grid_size_zero", {"--size", "0"}, "--size: the grid size must be at least 1, got 0"},
        BadInput{"unknown_variant", {"--size", "4", "--variant", "best"}, "unknown variant 'best'"},
        BadInput{"unknown_reference",
                 {"--size", "4", "--reference", "fv-nope"},
                 "unknown FV reference 'fv-nope'"},
        BadInput{"compare_endpoint",
                 {"--size", "4", "--compare-exact", "endpoint"},
                 "needs a fitted variant"},
        BadInput{"too_few_samples", {"--size", "4", "--fit-samples", "2"}, "--fit-samples"},
        BadInput{"clamp_out_of_range", {"--size", "4", "--clamp-degrees", "95"}, "grazing clamp"}),
    [](const ::testing::TestParamInfo<BadInput>& p) { return std::string(p.param.name); });

}  // namespace
}  // namespace shaderfit::cli
