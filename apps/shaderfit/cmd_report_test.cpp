#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>

#include "cli_test_util.hpp"
#include "shaderfit/plot/chart.hpp"

namespace shaderfit::cli {
namespace {

using testing::CliResult;
using testing::line_count;
using testing::run;
using testing::scratch_file;

const char* kFront = R"json({
  "inputs": ["r0", "x"],
  "data": {"source": "fresnel-seed (seed 1)", "rows": 4096, "target": "R"},
  "options": {"loss": "mse", "cost": "instructions", "seed": 1},
  "summary": {"total_time_s": 0.05},
  "front": [
    {"formula": "r0", "cost": 0, "mse": 0.0454, "max_abs": 0.98, "time_s": 0.001},
    {"formula": "r0 + (x - r0) * x^4", "cost": 4, "mse": 3.52e-4, "max_abs": 0.139, "time_s": 0.004},
    {"formula": "r0 + (x * 0.965 - r0) * x^4", "cost": 5, "mse": 2.8e-4, "max_abs": 0.12, "time_s": 0.9}
  ]
})json";

std::string scratch(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / "shaderfit_cli_report";
  std::filesystem::create_directories(dir);
  return (dir / name).string();
}

std::string find_chromium() {
  for (const char* name : {"chromium", "chromium-browser", "google-chrome"}) {
    const std::string cmd = std::string("command -v ") + name + " >/dev/null 2>&1";
    if (std::system(cmd.c_str()) == 0) return name;
  }
  return "";
}

std::string run_capture(const std::string& cmd) {
  std::string out;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return out;
  char buf[4096];
  while (std::size_t n = fread(buf, 1, sizeof buf, p)) out.append(buf, n);
  pclose(p);
  return out;
}

TEST(CliReport, SearchReportLoadsInHeadlessChromium) {
  if (!gnuplot_available()) GTEST_SKIP() << "skipped: gnuplot not found";
  const std::string html = scratch("search.html");
  CliResult r = run({"report", scratch_file("run.json", kFront), "--dataset", "fresnel-seed", "--baseline",
                     "Schlick=r0 + (1 - r0)*x^5", "-o", html});
  ASSERT_EQ(r.status, 0) << r.err;
  std::ifstream f(html);
  const std::string page((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  EXPECT_EQ(page.find("http://"), std::string::npos);  // nothing from the network
  EXPECT_EQ(page.find("https://"), std::string::npos);
  EXPECT_NE(page.find("r0 + (x - r0) * x^4"), std::string::npos);
  EXPECT_NE(page.find("float shaderfit_formula"), std::string::npos);  // GLSL code

  const std::string chromium = find_chromium();
  if (chromium.empty()) GTEST_SKIP() << "skipped: chromium not found";
  const std::string flags =
      " --headless --no-sandbox --disable-gpu --no-first-run --disable-background-networking"
      " --user-data-dir=" + scratch("profile") + " ";
  // The page's own check records on <body> how many images decoded at their size, and errors.
  const std::string dom = run_capture("timeout 120 " + chromium + flags + "--dump-dom 'file://" + html + "' 2>/dev/null");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(dom, m, std::regex(R"re(data-images-ok="(\d+)" data-images-total="(\d+)" data-errors="(\d+)")re")))
      << dom.substr(0, 400);
  EXPECT_EQ(m[1], m[2]);
  EXPECT_EQ(m[2], "3");  // Pareto front and two reflectance curves
  EXPECT_EQ(m[3], "0");
  const std::string shot = scratch("search.png");
  std::filesystem::remove(shot);
  run_capture("timeout 120 " + chromium + flags + "--window-size=1200,2000 --screenshot=" + shot + " 'file://" + html +
              "' 2>/dev/null");
  ASSERT_TRUE(std::filesystem::exists(shot));
  EXPECT_GT(std::filesystem::file_size(shot), 20000u);
}

TEST(CliReport, GenericRunJson) {
  const std::string html = scratch("fit.html");
  CliResult r = run({"report", scratch_file("fit.json", R"({"schema": "shaderfit.fit/1", "loss": "mse",
      "parameters": [{"group": "metal 0.3+3i", "s": 0.25}, {"group": "ior1.5", "s": 1.0}]})"),
                     "-o", html});
  ASSERT_EQ(r.status, 0) << r.err;
  std::ifstream f(html);
  const std::string page((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  EXPECT_NE(page.find("metal 0.3+3i"), std::string::npos);
  EXPECT_NE(page.find("shaderfit.fit/1"), std::string::npos);
}

struct BadReport {
  const char* name;
  const char* json;
  std::vector<std::string> extra;
  const char* expected;
};

void PrintTo(const BadReport& b, std::ostream* os) { *os << b.name; }

class CliReportErrors : public ::testing::TestWithParam<BadReport> {};

TEST_P(CliReportErrors, OneClearLineAndStatus2) {
  const BadReport& b = GetParam();
  std::vector<std::string> args = {"report", b.json ? scratch_file(std::string(b.name) + ".json", b.json)
                                                    : "/nonexistent/run.json",
                                   "-o", scratch("bad.html")};
  args.insert(args.end(), b.extra.begin(), b.extra.end());
  CliResult r = run(args);
  EXPECT_EQ(r.status, 2) << r.out << r.err;
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find(b.expected), std::string::npos) << r.err;
}

INSTANTIATE_TEST_SUITE_P(
    All, CliReportErrors,
    ::testing::Values(BadReport{"missing", nullptr, {}, "cannot open"},
                      BadReport{"not_json", "{front: ", {}, "not JSON"},
                      BadReport{"empty_front", R"({"front": []})", {}, "no front to report"},
                      BadReport{"unknown_baseline_variable", kFront, {"--dataset", "fresnel-seed", "--baseline", "r0 + y"},
                                "unknown variable 'y'"}),
    [](const ::testing::TestParamInfo<BadReport>& p) { return std::string(p.param.name); });

}  // namespace
}  // namespace shaderfit::cli
