#include <gtest/gtest.h>
#include <zlib.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "cli_test_util.hpp"
#include "shaderfit/plot/chart.hpp"
#include "shaderfit/report/html.hpp"

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
  CliResult r = run({"report", scratch_file("run.json", kFront), "--dataset", "fresnel-seed",
                     "--baseline", "Schlick=r0 + (1 - r0)*x^5", "-o", html});
  ASSERT_EQ(r.status, 0) << r.err;
  std::ifstream f(html);
  const std::string page((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  EXPECT_EQ(page.find("http://"), std::string::npos);  // nothing from the network
  EXPECT_EQ(page.find("https://"), std::string::npos);
  EXPECT_NE(page.find("r0 + (x - r0) * x^4"), std::string::npos);
  EXPECT_NE(page.find("float shaderfit_formula"), std::string::npos);  // GLSL code
  // The answer first (issue 42): the chosen formula, its code as tabs and the baselines before
  // the front; the data, settings and run last, folded.
  const std::size_t chosen = page.find("<h2>Chosen formula</h2>"),
                    tabs = page.find("<div class=\"tabs\">"),
                    against = page.find("<h2>Against the baselines</h2>"),
                    front = page.find("<h2>Pareto front</h2>"),
                    folded = page.find("<details><summary>Data, settings and run</summary>");
  ASSERT_NE(folded, std::string::npos) << page.substr(0, 2000);
  EXPECT_LT(chosen, tabs);
  EXPECT_LT(tabs, against);
  EXPECT_LT(against, front);
  EXPECT_LT(front, folded);
  EXPECT_NE(page.find("<summary>Data, settings and run</summary>\n<table>", folded - 1),
            std::string::npos);

  const std::string chromium = find_chromium();
  if (chromium.empty()) GTEST_SKIP() << "skipped: chromium not found";
  const std::string flags =
      " --headless --no-sandbox --disable-gpu --no-first-run --disable-background-networking"
      " --user-data-dir=" +
      scratch("profile") + " ";
  // The page's own check records on <body> how many images decoded at their size, and errors.
  const std::string dom = run_capture("timeout 120 " + chromium + flags + "--dump-dom 'file://" +
                                      html + "' 2>/dev/null");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(
      dom, m,
      std::regex(R"re(data-images-ok="(\d+)" data-images-total="(\d+)" data-errors="(\d+)")re")))
      << dom.substr(0, 400);
  EXPECT_EQ(m[1], m[2]);
  EXPECT_EQ(m[2], "3");  // Pareto front and two reflectance curves
  EXPECT_EQ(m[3], "0");
  const std::string shot = scratch("search.png");
  std::filesystem::remove(shot);
  run_capture("timeout 120 " + chromium + flags + "--window-size=1200,2000 --screenshot=" + shot +
              " 'file://" + html + "' 2>/dev/null");
  ASSERT_TRUE(std::filesystem::exists(shot));
  EXPECT_GT(std::filesystem::file_size(shot), 20000u);
}

// A front whose chosen member (--choose cost=12) has a long formula: before plots kept their
// frame, its key entry squeezed the reflectance curves into a sliver.
const char* kLongFront = R"json({
  "inputs": ["r0", "x"],
  "data": {"source": "fresnel-seed (seed 1)", "rows": 4096, "target": "R"},
  "options": {"loss": "mse", "cost": "instructions", "seed": 1},
  "front": [
    {"formula": "r0", "cost": 0, "mse": 0.0454, "max_abs": 0.98, "time_s": 0.001},
    {"formula": "r0 + (x - r0) * x^4", "cost": 4, "mse": 3.52e-4, "max_abs": 0.139, "time_s": 0.004},
    {"formula": "(0.5829255932120166 * (x^2 - r0) + 0.054242242592447185) * (x^2 + 0.24518082818505846 - r0 * 0.37064515047767865)^2 + r0",
     "cost": 12, "mse": 1.9e-4, "max_abs": 0.1, "time_s": 2.5}
  ]
})json";

// An 8-bit RGB or RGBA PNG (what Chromium's --screenshot writes) as RGB bytes, row 0 on top.
struct Pixels {
  std::size_t width = 0, height = 0;
  std::vector<std::uint8_t> rgb;
  [[nodiscard]] const std::uint8_t* at(std::size_t x, std::size_t y) const {
    return &rgb[3 * (y * width + x)];
  }
};

bool decode_png(const std::string& path, Pixels* out, std::string* why) {
  std::ifstream f(path, std::ios::binary);
  const std::vector<std::uint8_t> b((std::istreambuf_iterator<char>(f)),
                                    std::istreambuf_iterator<char>());
  if (b.size() < 8 || std::memcmp(b.data(), "\x89PNG\r\n\x1a\n", 8) != 0)
    return *why = "no PNG signature", false;
  auto be32 = [&](std::size_t o) {
    return (std::size_t{b[o]} << 24) | (std::size_t{b[o + 1]} << 16) |
           (std::size_t{b[o + 2]} << 8) | b[o + 3];
  };
  std::vector<std::uint8_t> z;
  std::size_t channels = 0;
  for (std::size_t pos = 8; pos + 12 <= b.size();) {
    const std::size_t len = be32(pos);
    if (pos + 12 + len > b.size()) return *why = "truncated chunk", false;
    const std::string type(reinterpret_cast<const char*>(&b[pos + 4]), 4);
    if (type == "IHDR") {
      out->width = be32(pos + 8);
      out->height = be32(pos + 12);
      channels = b[pos + 17] == 2 ? 3 : b[pos + 17] == 6 ? 4 : 0;
      if (b[pos + 16] != 8 || channels == 0 || b[pos + 20] != 0)
        return *why = "not 8-bit RGB(A), not interlaced", false;
    }
    if (type == "IDAT")
      z.insert(z.end(), b.begin() + static_cast<std::ptrdiff_t>(pos + 8),
               b.begin() + static_cast<std::ptrdiff_t>(pos + 8 + len));
    pos += 12 + len;
  }
  const std::size_t stride = out->width * channels;
  std::vector<std::uint8_t> raw(out->height * (stride + 1));
  uLongf n = raw.size();
  if (channels == 0 || uncompress(raw.data(), &n, z.data(), z.size()) != Z_OK || n != raw.size())
    return *why = "bad image data", false;
  std::vector<std::uint8_t> prev(stride, 0), cur(stride);
  out->rgb.resize(out->width * out->height * 3);
  for (std::size_t y = 0; y < out->height; ++y) {
    const std::uint8_t filter = raw[y * (stride + 1)];
    const std::uint8_t* in = &raw[y * (stride + 1) + 1];
    for (std::size_t x = 0; x < stride; ++x) {
      const int a = x >= channels ? cur[x - channels] : 0, up = prev[x],
                c = x >= channels ? prev[x - channels] : 0;
      int v = in[x];
      switch (filter) {
        case 0: break;
        case 1: v += a; break;
        case 2: v += up; break;
        case 3: v += (a + up) / 2; break;
        case 4: {
          const int p = a + up - c, pa = std::abs(p - a), pb = std::abs(p - up),
                    pc = std::abs(p - c);
          v += pa <= pb && pa <= pc ? a : pb <= pc ? up : c;
          break;
        }
        default: return *why = "bad filter", false;
      }
      cur[x] = static_cast<std::uint8_t>(v);
    }
    for (std::size_t x = 0; x < out->width; ++x)
      std::memcpy(&out->rgb[3 * (y * out->width + x)], &cur[x * channels], 3);
    std::swap(prev, cur);
  }
  return true;
}

struct Box {
  long x = 0, y = 0, w = 0, h = 0;
};

// The plot frame inside `image` (an image's box in the screenshot): the bounding box of the rows
// and columns where the frame's dark grey border (#404040, plot/chart.hpp) runs across at least
// 40% of the image. Empty when there is none.
Box find_frame(const Pixels& p, const Box& image) {
  auto border = [&](long x, long y) {
    const std::uint8_t* c = p.at(static_cast<std::size_t>(x), static_cast<std::size_t>(y));
    const int lo = std::min({c[0], c[1], c[2]}), hi = std::max({c[0], c[1], c[2]});
    return lo >= 40 && hi <= 140 && hi - lo <= 12;
  };
  long top = -1, bottom = -1, left = -1, right = -1;
  for (long y = image.y; y < image.y + image.h; ++y) {
    long n = 0;
    for (long x = image.x; x < image.x + image.w; ++x) n += border(x, y);
    if (n >= image.w * 4 / 10) {
      if (top < 0) top = y;
      bottom = y;
    }
  }
  for (long x = image.x; x < image.x + image.w; ++x) {
    long n = 0;
    for (long y = image.y; y < image.y + image.h; ++y) n += border(x, y);
    if (n >= image.h * 4 / 10) {
      if (left < 0) left = x;
      right = x;
    }
  }
  if (top < 0 || left < 0) return {};
  return {left, top, right - left + 1, bottom - top + 1};
}

// Pixels inside the frame that are neither the white background nor the light grey grid.
double drawn_share(const Pixels& p, const Box& f) {
  long drawn = 0;
  for (long y = f.y + 2; y < f.y + f.h - 2; ++y)
    for (long x = f.x + 2; x < f.x + f.w - 2; ++x) {
      const std::uint8_t* c = p.at(static_cast<std::size_t>(x), static_cast<std::size_t>(y));
      drawn += std::min({c[0], c[1], c[2]}) < 200;
    }
  return static_cast<double>(drawn) / static_cast<double>(std::max(1L, (f.w - 4) * (f.h - 4)));
}

std::string slurp_text(const std::string& path) {
  std::ifstream f(path);
  return {(std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>()};
}

// The report of a search (SHADERFIT_REPORT_RUN names a search's JSON to check instead of the
// long-formula front): every figure's SVG has its title and axis labels, and in a headless
// Chromium screenshot of the page each plot's frame covers at least half of its image.
TEST(CliReport, PlotsKeepTheirAreaInHeadlessChromium) {
  if (!gnuplot_available()) GTEST_SKIP() << "skipped: gnuplot not found";
  const char* given = std::getenv("SHADERFIT_REPORT_RUN");
  const std::string run_json = given != nullptr ? given : scratch_file("long.json", kLongFront);
  const std::string html = scratch("plots.html");
  const auto figures = std::filesystem::path(scratch("figures"));
  std::filesystem::remove_all(figures);
  std::vector<std::string> args = {"report",     run_json,
                                   "--dataset",  "fresnel-seed",
                                   "--baseline", "Schlick=r0 + (1 - r0)*x^5",
                                   "--figures",  figures.string(),
                                   "-o",         html};
  if (given == nullptr) args.insert(args.end(), {"--choose", "cost=12"});
  CliResult r = run(args);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("chosen: "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("  how: "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("  why: "), std::string::npos) << r.out;
  const std::string page = slurp_text(html);
  EXPECT_NE(page.find("How: "), std::string::npos);
  EXPECT_NE(page.find("chosen (cost "), std::string::npos);

  // Title, x label and y label of each figure, as the SVG's text.
  struct Figure {
    const char* name;
    std::vector<std::string> texts;
  };
  const std::vector<Figure> expected = {
      {"front", {"Pareto front: MSE against cost", "cost [instructions]", "MSE (log scale)"}},
      {"curves-ior1.5",
       {"Reflectance of IOR 1.5", "angle of incidence θ [degrees]", "reflectance R"}},
      {"curves-aluminium",
       {"Reflectance of aluminium", "angle of incidence θ [degrees]", "reflectance R"}}};
  std::size_t svgs = 0;
  for (const auto& entry : std::filesystem::directory_iterator(figures))
    svgs += entry.path().extension() == ".svg";
  EXPECT_EQ(svgs, expected.size());
  for (const Figure& fig : expected) {
    const std::string svg = slurp_text((figures / (std::string(fig.name) + ".svg")).string());
    ASSERT_FALSE(svg.empty()) << fig.name;
    for (const std::string& t : fig.texts)
      EXPECT_NE(svg.find("<text>" + html_escape(t) + "</text>"), std::string::npos)
          << fig.name << ": " << t;
  }

  const std::string chromium = find_chromium();
  if (chromium.empty()) GTEST_SKIP() << "skipped: chromium not found";
  const std::string flags =
      " --headless --no-sandbox --disable-gpu --no-first-run --disable-background-networking"
      // A profile of its own: Chromium refuses a profile another test's instance holds.
      " --hide-scrollbars --force-device-scale-factor=1 --user-data-dir=" +
      scratch("profile-plots") + " ";
  const std::string dom =
      run_capture("timeout 120 " + chromium + flags +
                  "--window-size=1200,2000 --dump-dom 'file://" + html + "' 2>/dev/null");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(
      dom, m, std::regex(R"re(data-plot-boxes="([0-9,;]*)" data-page-height="(\d+)")re")))
      << dom.substr(0, 400);
  std::vector<Box> boxes;
  {
    std::stringstream list(m[1].str());
    std::string item;
    while (std::getline(list, item, ';')) {
      Box b;
      ASSERT_EQ(std::sscanf(item.c_str(), "%ld,%ld,%ld,%ld", &b.x, &b.y, &b.w, &b.h), 4) << item;
      boxes.push_back(b);
    }
  }
  ASSERT_EQ(boxes.size(), expected.size());
  const long height = std::stol(m[2].str());
  const std::string shot = scratch("plots.png");
  std::filesystem::remove(shot);
  run_capture("timeout 120 " + chromium + flags + "--window-size=1200," + std::to_string(height) +
              " --screenshot=" + shot + " 'file://" + html + "' 2>/dev/null");
  Pixels p;
  std::string why;
  ASSERT_TRUE(decode_png(shot, &p, &why)) << why;
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    const Box& b = boxes[i];
    ASSERT_TRUE(b.w > 0 && b.h > 0 && b.x + b.w <= static_cast<long>(p.width) &&
                b.y + b.h <= static_cast<long>(p.height))
        << "image " << i << " lies outside the " << p.width << " x " << p.height << " screenshot";
    const Box f = find_frame(p, b);
    const double share = static_cast<double>(f.w * f.h) / static_cast<double>(b.w * b.h);
    EXPECT_GE(share, 0.5) << expected[i].name << ": the frame " << f.w << " x " << f.h << " of a "
                          << b.w << " x " << b.h << " image";
    EXPECT_GT(drawn_share(p, f), 0.003) << expected[i].name << ": nothing drawn in the frame";
  }
}

TEST(CliReport, GenericRunJson) {
  const std::string html = scratch("fit.html");
  CliResult r =
      run({"report", scratch_file("fit.json", R"({"schema": "shaderfit.fit/1", "loss": "mse",
      "formula": "r0 + (1 - r0 - s*x) * x^4 * 0.5829255932120166",
      "parameters": [{"group": "metal 0.3+3i", "s": 0.25}, {"group": "ior1.5", "s": 1.0}],
      "blocks": [{"label": "all", "formula": "x2 * 1.0000000000000027 + 1e-05"}]})"),
           "-o", html});
  ASSERT_EQ(r.status, 0) << r.err;
  std::ifstream f(html);
  const std::string page((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  EXPECT_NE(page.find("metal 0.3+3i"), std::string::npos);
  EXPECT_NE(page.find("shaderfit.fit/1"), std::string::npos);
  // Formulas read as people read them: constants as float32 needs them, names kept.
  EXPECT_NE(page.find("r0 + (1 - r0 - s*x) * x^4 * 0.5829256"), std::string::npos);
  EXPECT_EQ(page.find("0.5829255932120166"), std::string::npos);
  EXPECT_NE(page.find("x2 * 1 + 1e-05"), std::string::npos);
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
  std::vector<std::string> args = {
      "report",
      b.json ? scratch_file(std::string(b.name) + ".json", b.json) : "/nonexistent/run.json", "-o",
      scratch("bad.html")};
  args.insert(args.end(), b.extra.begin(), b.extra.end());
  CliResult r = run(args);
  EXPECT_EQ(r.status, 2) << r.out << r.err;
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find(b.expected), std::string::npos) << r.err;
}

INSTANTIATE_TEST_SUITE_P(
    All, CliReportErrors,
    ::testing::Values(
        BadReport{"missing", nullptr, {}, "cannot open"},
        BadReport{"not_json", "{front: ", {}, "not JSON"},
        BadReport{"empty_front", R"({"front": []})", {}, "no front to report"},
        BadReport{"bad_choice", kFront, {"--choose", "cost=abc"}, "--choose: expected a number"},
        BadReport{"bad_chosen_formula", kFront, {"--choose", "r0 + y"}, "unknown variable 'y'"},
        BadReport{"unknown_baseline_variable",
                  kFront,
                  {"--dataset", "fresnel-seed", "--baseline", "r0 + y"},
                  "unknown variable 'y'"}),
    [](const ::testing::TestParamInfo<BadReport>& p) { return std::string(p.param.name); });

}  // namespace
}  // namespace shaderfit::cli
