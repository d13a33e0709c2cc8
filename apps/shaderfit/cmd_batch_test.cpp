#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cli_test_util.hpp"

namespace shaderfit::cli::testing {
namespace {

namespace fs = std::filesystem;

// The issue's manifest with a candidate budget instead of 5 seconds, and a small CSV.
std::string issue_manifest(const std::string& extra = "") {
  std::string csv = "r0,x,R\n";
  for (int i = 0; i <= 40; ++i) {
    const double x = i / 40.0, r0 = 0.04 + 0.02 * (i % 3);
    csv += std::to_string(r0) + "," + std::to_string(x) + "," +
           std::to_string(r0 + (1 - r0) * x * x * x * x * x * 0.9) + "\n";
  }
  scratch_file("fresnel.csv", csv);
  return "[defaults]\ntime = 600\nevals = 20000\nloss = \"max_abs\"\n\n"
         "[[function]]\nname = \"fast_tanh\"\nreference = \"tanh(x)\"\n"
         "domain = { x = [0.0, 4.0] }\nsamples = 300\n\n"
         "[[function]]\nname = \"fast_fresnel\"\ndata = \"fresnel.csv\"\n"
         "baseline = \"r0 + (1 - r0)*x^5\"\ngoal = \"beat-baseline\"\n" +
         extra;
}

TEST(CmdBatch, WritesTheHeadersTheJsonAndTheReport) {
  const std::string m = scratch_file("batch.toml", issue_manifest());
  const fs::path out = fs::path(m).parent_path() / "batch-out";
  fs::remove_all(out);
  const CliResult r = run({"batch", m, "--out", out.string(), "--parallel", "2"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("fast_tanh  cost"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("fast_fresnel  cost"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("goal met"), std::string::npos) << r.out;
  for (const char* f : {"fastmath.glsl", "fastmath.hlsl", "fastmath.h", "fastmath.metal",
                        "batch.json", "report.html", "entries/fast_tanh.json"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
  std::ifstream in(out / "batch.json");
  const auto doc = nlohmann::json::parse(in);
  EXPECT_EQ(doc.at("entries").size(), 2u);
  // Again: nothing is searched, every entry is read back.
  const CliResult again = run({"batch", m, "--out", out.string()});
  ASSERT_EQ(again.status, 0) << again.err;
  EXPECT_NE(again.out.find("(2 finished by an earlier run)"), std::string::npos) << again.out;
}

// A manifest's cost names the search's cost target: its costs are RDNA 2 counts.
TEST(CmdBatch, CostRdna2) {
  const std::string m = scratch_file(
      "batch_rdna.toml", "[defaults]\ntime = 600\nevals = 5000\ncost = \"rdna2\"\n\n"
                         "[[function]]\nname = \"fast_tanh\"\nreference = \"tanh(x)\"\n"
                         "domain = { x = [0.0, 4.0] }\nsamples = 200\n");
  const fs::path out = fs::path(m).parent_path() / "batch-rdna-out";
  fs::remove_all(out);
  const CliResult r = run({"batch", m, "--out", out.string()});
  ASSERT_EQ(r.status, 0) << r.err;
  std::ifstream in(out / "entries/fast_tanh.json");
  const auto doc = nlohmann::json::parse(in);
  EXPECT_EQ(doc.at("cost"), "rdna2");
  EXPECT_NE(r.out.find("fast_tanh  cost"), std::string::npos) << r.out;
}

TEST(CmdBatch, ABadEntryIsOneLineAndTheOthersRun) {
  const std::string m =
      scratch_file("bad.toml", issue_manifest("\n[[function]]\nname = \"oops\"\nreference = "
                                              "\"x^2\"\ndomain = { x = [0, 1] }\ntme = 5\n"));
  const fs::path out = fs::path(m).parent_path() / "bad-out";
  fs::remove_all(out);
  const CliResult r = run({"batch", m, "--out", out.string()});
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("bad.toml:22:1: entry 'oops': unknown key 'tme'"), std::string::npos)
      << r.err;
  EXPECT_NE(r.out.find("fast_tanh  cost"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(out / "fastmath.glsl"));

  const fs::path strict_out = fs::path(m).parent_path() / "strict-out";
  fs::remove_all(strict_out);
  expect_bad_input({"batch", m, "--out", strict_out.string(), "--strict"},
                   "bad.toml:22:1: entry 'oops': unknown key 'tme'");
  EXPECT_FALSE(fs::exists(strict_out));
}

TEST(CmdBatch, AManifestThatIsNotTomlIsOneLine) {
  const std::string m = scratch_file("broken.toml", "[defaults\ntime = 5\n");
  expect_bad_input({"batch", m}, "broken.toml:1:");
}

}  // namespace
}  // namespace shaderfit::cli::testing
