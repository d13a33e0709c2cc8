// Every command that reads data takes the same options for it (data_source.hpp): the CSV's and
// the built-in data sets', the reference's, and the inputs and target.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "cli_test_util.hpp"

namespace shaderfit::cli {
namespace {

using namespace testing;

TEST(DataOptions, EveryCommandThatReadsDataTakesTheSame) {
  const std::vector<std::vector<std::string>> commands = {
      {"search"},         {"eval"},        {"fit"},          {"report"},
      {"plot", "curves"}, {"plot", "map"}, {"plot", "front"}};
  for (const auto& command : commands) {
    std::vector<std::string> args = command;
    args.push_back("--help");
    const CliResult r = run(args);
    const std::string help = r.out + r.err;
    for (const char* flag : {"--data ", "--drop-missing", "--dataset", "--data-seed", "--inputs",
                             "--target", "--reference ", "--reference-file", "--function",
                             "--domain", "--define", "--samples", "--drop-nonfinite"})
      EXPECT_NE(help.find(flag), std::string::npos) << command.back() << " lacks " << flag;
  }
}

TEST(DataOptions, PlotAndReportTakeTheInputsAndTheTarget) {
  const std::string csv =
      scratch_file("plot_inputs.csv", "a,b,y,w\n0,1,0.5,1\n0.5,2,1.5,1\n1,3,2,1\n");
  // The target as every command infers it (the column named y), or as --target names it.
  const std::string png = scratch_file("plot_inputs.png", "");
  for (const char* target : {"", "w"}) {
    std::vector<std::string> args = {"plot", "map", "--data", csv, "--x",  "a",
                                     "--y",  "b",   "-o",     png, "a + b"};
    if (*target) args.insert(args.end() - 1, {"--target", target});
    const CliResult r = run(args);
    if (r.err.find("gnuplot") != std::string::npos) GTEST_SKIP() << "skipped: gnuplot not found";
    EXPECT_EQ(r.status, 0) << r.err;
  }
  expect_bad_input({"plot", "map", "--data", csv, "--x", "a", "--y", "b", "--inputs", "a,zz", "-o",
                    png, "a + b"},
                   "zz");
}

}  // namespace
}  // namespace shaderfit::cli
