#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "cli_test_util.hpp"
#include "shaderfit/plot/chart.hpp"

namespace shaderfit::cli {
namespace {

using testing::CliResult;
using testing::line_count;
using testing::run;
using testing::scratch_file;

std::string out_path(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / "shaderfit_cli_plot";
  std::filesystem::create_directories(dir);
  return (dir / name).string();
}

TEST(CliPlot, CurvesFrontAndMap) {
  if (!gnuplot_available()) GTEST_SKIP() << "skipped: gnuplot not found";
  CliResult c = run({"plot", "curves", "--material", "aluminium", "-o", out_path("al.svg"),
                     "Schlick=r0 + (1 - r0)*x^5", "r0 + (x - r0)*x^4"});
  ASSERT_EQ(c.status, 0) << c.err;
  EXPECT_NE(c.out.find("3 curves"), std::string::npos);
  CliResult e = run({"plot", "curves", "--dataset", "fresnel-seed", "--x", "cos_theta", "--group",
                     "kind", "--errors", "-o", out_path("err.png"), "r0 + (x - r0)*x^4"});
  ASSERT_EQ(e.status, 0) << e.err;
  const std::string front = scratch_file("front.json",
                                         R"({"front": [{"formula": "r0", "cost": 0, "mse": 0.05},
                                                       {"formula": "r0 + (x - r0)*x^4", "cost": 4, "mse": 3.5e-4}]})");
  CliResult f = run({"plot", "front", front, "--dataset", "fresnel-seed", "-o",
                     out_path("front.png"), "--mark", "Schlick=r0 + (1 - r0)*x^5"});
  ASSERT_EQ(f.status, 0) << f.err;
  EXPECT_NE(f.out.find("1 marked"), std::string::npos);
  CliResult m = run({"plot", "map", "--dataset", "fresnel-seed", "--x", "cos_theta", "--y", "r0",
                     "--bins", "16", "-o", out_path("map.png"), "r0 + (1 - r0)*x^5"});
  ASSERT_EQ(m.status, 0) << m.err;
  // Seed 002's sphere: three titled panels in one image.
  CliResult sp = run({"plot", "sphere", "--size", "32", "-o", out_path("sphere.svg")});
  ASSERT_EQ(sp.status, 0) << sp.err;
  std::ifstream svg(out_path("sphere.svg"));
  const std::string text((std::istreambuf_iterator<char>(svg)), std::istreambuf_iterator<char>());
  for (const char* title : {">reference<", ">approximation<", ">|difference| x 8<", ">GGX sphere"})
    EXPECT_NE(text.find(title), std::string::npos) << title;
}

struct BadPlot {
  const char* name;
  std::vector<std::string> args;
  const char* expected;
};

void PrintTo(const BadPlot& b, std::ostream* os) { *os << b.name; }

class CliPlotErrors : public ::testing::TestWithParam<BadPlot> {};

TEST_P(CliPlotErrors, OneClearLineAndStatus2) {
  std::vector<std::string> args = GetParam().args;
  for (auto& a : args) {
    if (a == "@empty_front") a = scratch_file("empty_front.json", R"({"front": []})");
    if (a == "@out") a = out_path("bad.png");
  }
  CliResult r = run(args);
  EXPECT_EQ(r.status, 2) << r.out << r.err;
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find(GetParam().expected), std::string::npos) << r.err;
}

INSTANTIATE_TEST_SUITE_P(
    All, CliPlotErrors,
    ::testing::Values(
        BadPlot{"unknown_formula_variable",
                {"plot", "curves", "--material", "1.5", "-o", "@out", "r0 + y"},
                "formula 1:1:6: unknown variable 'y'"},
        BadPlot{"formula_syntax",
                {"plot", "curves", "--material", "1.5", "-o", "@out", "r0 +"},
                "formula 1:1:5"},
        BadPlot{"unknown_group",
                {"plot", "curves", "--dataset", "fresnel-seed", "--x", "cos_theta", "--group",
                 "colour", "-o", "@out"},
                "no column 'colour'"},
        BadPlot{"unknown_material",
                {"plot", "curves", "--material", "unobtainium", "-o", "@out"},
                "unknown material 'unobtainium'"},
        BadPlot{"empty_front", {"plot", "front", "@empty_front", "-o", "@out"}, "no front to plot"},
        BadPlot{"missing_front",
                {"plot", "front", "/nonexistent/front.json", "-o", "@out"},
                "cannot open"},
        BadPlot{"range",
                {"plot", "curves", "--material", "1.5", "--x-range", "90,0", "-o", "@out"},
                "--x-range: range has min >= max"},
        BadPlot{"range_syntax",
                {"plot", "curves", "--material", "1.5", "--y-range", "0;1", "-o", "@out"},
                "expected MIN,MAX"},
        BadPlot{"bad_extension",
                {"plot", "curves", "--material", "1.5", "-o", "plot.jpg"},
                "use a .png or .svg"},
        BadPlot{"bins",
                {"plot", "map", "--material", "1.5", "--x", "x", "--y", "r0", "--bins", "0", "-o",
                 "@out", "r0"},
                "--bins must be at least 1"}),
    [](const ::testing::TestParamInfo<BadPlot>& p) { return std::string(p.param.name); });

}  // namespace
}  // namespace shaderfit::cli
