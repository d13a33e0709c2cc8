#include <gtest/gtest.h>

#include <algorithm>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "shaderfit/core/error.hpp"
#include "shaderfit/plot/chart.hpp"

namespace shaderfit {
namespace {

Chart two_curves() {
  Chart c;
  c.title = "test \"quoted\" title";
  c.x_label = "angle [degrees]";
  c.y_label = "reflectance";
  Series a{"exact", {0, 45, 90}, {0.04, 0.05, 1.0}};
  a.emphasis = true;
  c.series.push_back(a);
  c.series.push_back({"r0 + (x - r0)*x^4", {0, 45, 90}, {0.04, 0.052, 1.0}});
  c.markers.push_back({"Schlick", 6, 5e-4});
  return c;
}

// Width and height from a PNG's IHDR chunk.
std::pair<int, int> png_size(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  unsigned char h[24] = {};
  f.read(reinterpret_cast<char*>(h), 24);
  EXPECT_EQ(h[1], 'P');
  EXPECT_EQ(h[12], 'I');
  auto be = [&](int o) { return (h[o] << 24) | (h[o + 1] << 16) | (h[o + 2] << 8) | h[o + 3]; };
  return {be(16), be(20)};
}

TEST(PlotScript, ChartHasDataStylesAndEscapes) {
  std::string s = gnuplot_script(two_curves(), ImageFormat::Svg, "out.svg");
  EXPECT_NE(s.find("set terminal svg size 900,560"), std::string::npos);
  EXPECT_NE(s.find("set title \"test \\\"quoted\\\" title\""), std::string::npos) << s;
  EXPECT_NE(s.find("$d1 << EOD\n0 0.040000000000000001"), std::string::npos) << s;
  EXPECT_NE(s.find("lc rgb '#000000' dt 1"), std::string::npos);  // reference: black, solid
  EXPECT_NE(s.find("lc rgb '#0072B2' dt 2"), std::string::npos);  // next: blue, dashed
  EXPECT_NE(s.find("set label \"Schlick\" at 6,0.0005"), std::string::npos);
}

TEST(PlotScript, FrameKeepsItsShareWhateverTheLabels) {
  Chart shorts = two_curves(), longs = two_curves();
  for (int i = 0; i < 22; ++i) {
    shorts.series.push_back({"s" + std::to_string(i), {0, 1}, {0, 1}});
    longs.series.push_back({std::string(300, 'x') + std::to_string(i), {0, 1}, {0, 1}});
  }
  const PixelBox a = chart_frame(shorts), b = chart_frame(longs);
  EXPECT_EQ(a.width, b.width);
  EXPECT_EQ(a.height, b.height);
  const Chart base = two_curves();
  for (const Chart* c : std::initializer_list<const Chart*>{&base, &shorts}) {
    const PixelBox f = chart_frame(*c);
    EXPECT_GE(static_cast<double>(f.width) * f.height, 0.55 * c->width * c->height);
  }
  const std::string s = gnuplot_script(longs, ImageFormat::Png, "x.png");
  EXPECT_EQ(s.find(std::string(300, 'x')), std::string::npos);  // cut to fit the key
  EXPECT_NE(s.find("xxx…\""), std::string::npos);
  EXPECT_NE(s.find("set lmargin at screen"), std::string::npos);
  EXPECT_NE(s.find("set key at screen"), std::string::npos);
}

Heatmap small_map(const std::string& title) {
  Heatmap m;
  m.title = title;
  m.x_label = "roughness";
  m.y_label = "sqrt(F0)";
  m.value_label = "max |error|";
  m.nx = 3;
  m.ny = 2;
  m.values = {1e-4, 1e-3, 0, 1e-2, 2e-2, 3e-2};
  m.log_values = true;
  return m;
}

TEST(PlotScript, AnErrorMapOfZerosIsDrawnLinear) {
  // An exact formula's error map: no value a log scale can show, so a linear one from 0.
  Heatmap m = small_map("exact");
  std::fill(m.values.begin(), m.values.end(), 0.0);
  HeatmapGrid g;
  g.panels.push_back(m);
  const std::string s = gnuplot_script(g, ImageFormat::Svg, "g.svg");
  EXPECT_EQ(s.find("\nset logscale cb"), std::string::npos) << s;
  EXPECT_NE(s.find("set cbrange [0:1]"), std::string::npos) << s;
  EXPECT_EQ(s.find(" NaN\n"), std::string::npos);
}

TEST(PlotScript, HeatmapGridHasATitledPanelEach) {
  HeatmapGrid g;
  g.title = "errors";
  for (const char* t : {"mean log2", "max log2", "mean abs"}) g.panels.push_back(small_map(t));
  const std::string s = gnuplot_script(g, ImageFormat::Svg, "g.svg");
  EXPECT_NE(s.find("set multiplot title \"errors\""), std::string::npos) << s;
  for (const char* t : {"\"mean log2\"", "\"max log2\"", "\"mean abs\"", "$map2 << EOD"})
    EXPECT_NE(s.find(t), std::string::npos) << t;
  EXPECT_NE(s.find("set logscale cb"), std::string::npos);
  EXPECT_NE(s.find("set cblabel \"max |error| (log scale)\""), std::string::npos);
  EXPECT_NE(s.find(" NaN\n"), std::string::npos);  // the 0 on a log scale: blank
  EXPECT_NE(s.find("unset multiplot"), std::string::npos);
  HeatmapGrid none;
  EXPECT_THROW(gnuplot_script(none, ImageFormat::Png, "g.png"), Error);
  HeatmapGrid no_columns = g;
  no_columns.columns = 0;
  EXPECT_THROW(gnuplot_script(no_columns, ImageFormat::Png, "g.png"), Error);
  HeatmapGrid ragged = g;
  ragged.panels[1].values.pop_back();
  EXPECT_THROW(gnuplot_script(ragged, ImageFormat::Png, "g.png"), Error);
}

TEST(PlotScript, BadChartsAreRefused) {
  Chart empty;
  EXPECT_THROW(gnuplot_script(empty, ImageFormat::Png, "x.png"), Error);
  Chart ragged = two_curves();
  ragged.series[1].y.pop_back();
  EXPECT_THROW(gnuplot_script(ragged, ImageFormat::Png, "x.png"), Error);
  Chart bad_range = two_curves();
  bad_range.x_range = Range{1, 1};
  try {
    gnuplot_script(bad_range, ImageFormat::Png, "x.png");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("min >= max"), std::string::npos);
  }
  Chart log_neg = two_curves();
  log_neg.log_y = true;
  for (auto& s : log_neg.series)
    for (auto& y : s.y) y = -1;
  EXPECT_THROW(gnuplot_script(log_neg, ImageFormat::Png, "x.png"), Error);
  EXPECT_THROW(image_format_for("plot.jpg"), Error);
  Heatmap m;
  m.nx = 2;
  m.ny = 2;
  m.values = {1, 2, 3};
  EXPECT_THROW(gnuplot_script(m, ImageFormat::Png, "m.png"), Error);
}

TEST(PlotRender, PngAndSvgFiles) {
  if (!gnuplot_available()) GTEST_SKIP() << "skipped: gnuplot not found";
  const auto dir = std::filesystem::temp_directory_path() / "shaderfit_plot_test";
  std::filesystem::create_directories(dir);
  const std::string png = (dir / "chart.png").string(), svg = (dir / "chart.svg").string();
  render(two_curves(), png);
  EXPECT_EQ(png_size(png), std::make_pair(900, 560));
  render(two_curves(), svg);
  std::ifstream f(svg);
  std::string text((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("<svg"), std::string::npos);
  EXPECT_NE(text.find("exact"), std::string::npos);

  Heatmap m;
  m.title = "log2 error";
  m.x_label = "roughness";
  m.y_label = "sqrt(F0)";
  m.value_label = "max |log2 error|";
  m.nx = 16;
  m.ny = 8;
  m.x_range = {0, 1};
  m.y_range = {0, 1};
  m.log_values = true;
  for (int j = 0; j < m.ny; ++j)
    for (int i = 0; i < m.nx; ++i) m.values.push_back(std::pow(10.0, -4 + 0.2 * i + 0.1 * j));
  m.values[3] = 0;  // drawn blank on a log scale
  const std::string map_png = (dir / "map.png").string();
  render(m, map_png);
  EXPECT_EQ(png_size(map_png), std::make_pair(760, 640));

  HeatmapGrid g;
  g.title = "four maps";
  for (const char* t : {"a", "b", "c", "d"}) g.panels.push_back(small_map(t));
  const std::string grid_png = (dir / "grid.png").string(), grid_svg = (dir / "grid.svg").string();
  render(g, grid_png);
  EXPECT_EQ(png_size(grid_png), std::make_pair(g.width, g.height));
  render(g, grid_svg);
  std::ifstream gf(grid_svg);
  const std::string grid_text((std::istreambuf_iterator<char>(gf)),
                              std::istreambuf_iterator<char>());
  for (const char* t : {">four maps<", ">roughness<", ">sqrt(F0)<", ">max |error| (log scale)<"})
    EXPECT_NE(grid_text.find(t), std::string::npos) << t;
}

}  // namespace
}  // namespace shaderfit
