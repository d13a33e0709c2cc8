// Chart and heat-map rendering through gnuplot. The whole program, data included, is one script
// (inline data blocks), so what is rendered can be saved and re-run by hand.
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "shaderfit/core/error.hpp"
#include "shaderfit/plot/chart.hpp"

namespace shaderfit {

namespace {

// Okabe-Ito, black first for the reference, yellow last (weak on white).
constexpr const char* kColours[] = {"#000000", "#0072B2", "#D55E00", "#009E73",
                                    "#CC79A7", "#E69F00", "#56B4E9", "#F0E442"};
// Dash patterns and point shapes that tell series apart without colour.
constexpr const char* kDashes[] = {"1", "2", "4", "5", "(12,4,2,4)", "3", "(2,3)", "(16,6)"};
constexpr int kPoints[] = {7, 5, 9, 13, 11, 4, 6, 8};
constexpr int kStyles = 8;

std::string quote(const std::string& s) {
  std::string q = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') q += '\\';
    if (c == '\n') {
      q += "\\n";
      continue;
    }
    q += c;
  }
  return q + "\"";
}

std::string number(double v) {
  if (!std::isfinite(v)) return "NaN";
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}

std::string terminal(ImageFormat format, int width, int height) {
  std::ostringstream s;
  if (format == ImageFormat::Png) {
    s << "set terminal pngcairo size " << width << "," << height
      << " noenhanced font 'DejaVu Sans,11' linewidth 1.4\n";
  } else {
    s << "set terminal svg size " << width << "," << height
      << " noenhanced font 'DejaVu Sans,11' linewidth 1.4 background '#ffffff'\n";
  }
  return s.str();
}

constexpr const char* kBorder = "'#404040'";

// Margins in pixels: room for the title, the y tic labels and label, the x tic labels and label.
constexpr int kLeftPx = 96, kRightPx = 24, kTitlePx = 38, kNoTitlePx = 16, kAxisBelowPx = 62;
// The key's band under the frame: rows of kKeyRowPx, at most kKeyRows of them.
constexpr int kKeyRowPx = 19, kKeyPadPx = 14, kKeyRows = 4, kKeyMaxColumns = 3;
constexpr double kKeyBottomPx = 6, kCharPx = 7;
// Heat maps: the colour bar, its tic labels and its label on the right.
constexpr int kColourBarPx = 130;

struct ChartLayout {
  PixelBox frame;
  int key_columns = 1;
  std::size_t key_label_chars = 0;  // the longest label that fits a column
};

ChartLayout chart_layout(const Chart& c) {
  ChartLayout l;
  const int n = static_cast<int>(c.series.size());
  l.key_columns = std::max(1, std::min(n, kKeyMaxColumns));
  if ((n + l.key_columns - 1) / l.key_columns > kKeyRows)
    l.key_columns = (n + kKeyRows - 1) / kKeyRows;
  const int rows = n == 0 ? 0 : (n + l.key_columns - 1) / l.key_columns;
  const int top = c.title.empty() ? kNoTitlePx : kTitlePx;
  const int bottom = kAxisBelowPx + (rows > 0 ? rows * kKeyRowPx + kKeyPadPx : 0);
  l.frame = {kLeftPx, top, std::max(1, c.width - kLeftPx - kRightPx),
             std::max(1, c.height - top - bottom)};
  const double column_px = (c.width - 40.0) / l.key_columns;
  l.key_label_chars = static_cast<std::size_t>(std::max(8.0, column_px / kCharPx - 6));
  return l;
}

// gnuplot margins that put the frame at `frame` (pixels from the top left) in a w x h image.
std::string margins(int w, int h, const PixelBox& frame) {
  std::ostringstream s;
  s << "set lmargin at screen " << number(static_cast<double>(frame.left) / w) << "\n"
    << "set rmargin at screen " << number(static_cast<double>(frame.left + frame.width) / w) << "\n"
    << "set tmargin at screen " << number(1 - static_cast<double>(frame.top) / h) << "\n"
    << "set bmargin at screen " << number(1 - static_cast<double>(frame.top + frame.height) / h)
    << "\n";
  return s.str();
}

// `label` cut to `chars` characters (UTF-8 code points), the last one "…" when cut.
std::string fit_label(const std::string& label, std::size_t chars) {
  std::size_t count = 0;
  for (std::size_t i = 0; i < label.size(); ++i) {
    if ((static_cast<unsigned char>(label[i]) & 0xC0) == 0x80) continue;
    if (++count == chars) {
      std::size_t end = i + 1;
      while (end < label.size() && (static_cast<unsigned char>(label[end]) & 0xC0) == 0x80) ++end;
      return end >= label.size() ? label : label.substr(0, i) + "…";
    }
  }
  return label;
}

void check_range(const std::optional<Range>& r, const char* axis) {
  if (r && !(r->min < r->max)) {
    throw Error(std::string(axis) + " range has min >= max (" + number(r->min) +
                    " >= " + number(r->max) + ")",
                SourceLocation{std::string("--") + axis + "-range"});
  }
}

}  // namespace

ImageFormat image_format_for(const std::string& path) {
  const std::string ext = std::filesystem::path(path).extension().string();
  if (ext == ".png" || ext == ".PNG") return ImageFormat::Png;
  if (ext == ".svg" || ext == ".SVG") return ImageFormat::Svg;
  throw Error("cannot tell the image format of '" + path + "': use a .png or .svg file name",
              SourceLocation{path});
}

std::string gnuplot_script(const Chart& c, ImageFormat format, const std::string& output) {
  if (c.series.empty() && c.markers.empty())
    throw Error("nothing to plot: the chart has no series");
  check_range(c.x_range, "x");
  check_range(c.y_range, "y");
  std::ostringstream s;
  s << terminal(format, c.width, c.height) << "set output " << quote(output) << "\n";
  if (!c.title.empty()) s << "set title " << quote(c.title) << "\n";
  s << "set xlabel " << quote(c.x_label) << "\nset ylabel " << quote(c.y_label) << "\n";
  s << "set grid lc rgb '#d9d9d9' lw 0.6\nset border lc rgb " << kBorder << "\n";
  const ChartLayout layout = chart_layout(c);
  s << margins(c.width, c.height, layout.frame);
  // The key sits in its own band under the frame, in columns; labels too long for a column
  // are cut (the caller puts formulas in a caption or a table).
  s << "set key at screen 0.5, screen " << number(kKeyBottomPx / c.height)
    << " center bottom horizontal maxcols " << layout.key_columns
    << " Left reverse samplen 3 spacing 1.1 width 1\n";
  if (c.log_x) s << "set logscale x\nset format x '10^{%L}'\nset format x '%g'\n";
  if (c.log_y) s << "set logscale y\nset format y '%g'\n";
  if (c.x_range)
    s << "set xrange [" << number(c.x_range->min) << ":" << number(c.x_range->max) << "]\n";
  if (c.y_range)
    s << "set yrange [" << number(c.y_range->min) << ":" << number(c.y_range->max) << "]\n";
  bool any_positive_y = false;
  for (std::size_t i = 0; i < c.series.size(); ++i) {
    const Series& sr = c.series[i];
    if (sr.x.size() != sr.y.size()) {
      throw Error("series '" + sr.label + "' has " + std::to_string(sr.x.size()) +
                  " x values and " + std::to_string(sr.y.size()) + " y values");
    }
    s << "$d" << i << " << EOD\n";
    for (std::size_t k = 0; k < sr.x.size(); ++k) {
      s << number(sr.x[k]) << " " << number(sr.y[k]) << "\n";
      any_positive_y = any_positive_y || sr.y[k] > 0;
    }
    s << "EOD\n";
  }
  if (c.log_y && !c.series.empty() && !any_positive_y) {
    throw Error("logarithmic y axis, but no series has a positive value");
  }
  for (const Marker& m : c.markers) {
    s << "set label " << quote(m.label) << " at " << number(m.x) << "," << number(m.y)
      << " point pt 6 ps 2.2 lc rgb '#000000' offset 1.2,0.9 front\n";
  }
  s << "plot ";
  if (c.series.empty()) s << "NaN notitle";
  for (std::size_t i = 0; i < c.series.size(); ++i) {
    const Series& sr = c.series[i];
    const int k = static_cast<int>(i % kStyles);
    const double width = sr.emphasis ? 2.6 : 1.6;
    s << (i ? ", \\\n     " : "") << "$d" << i << " using 1:2 with ";
    switch (sr.style) {
      case Series::Style::Lines: s << (c.step_series ? "steps" : "lines"); break;
      case Series::Style::Points: s << "points ps 0.5"; break;
      case Series::Style::LinesPoints: s << "linespoints pi 1"; break;
    }
    s << " lw " << width << " lc rgb '" << kColours[k] << "' dt " << kDashes[k] << " pt "
      << kPoints[k];
    if (sr.style != Series::Style::Points) s << " ps 1.1";
    s << " title " << quote(fit_label(sr.label, layout.key_label_chars));
  }
  s << "\n";
  return s.str();
}

namespace {

void check_heatmap(const Heatmap& m) {
  if (m.nx <= 0 || m.ny <= 0) throw Error("heat map has no cells");
  if (m.values.size() != static_cast<std::size_t>(m.nx) * static_cast<std::size_t>(m.ny)) {
    throw Error("heat map values (" + std::to_string(m.values.size()) + ") don't fill its " +
                std::to_string(m.nx) + " x " + std::to_string(m.ny) + " grid");
  }
  check_range(m.x_range, "x");
  check_range(m.y_range, "y");
}

// One heat map drawn in `frame` of a w x h image, its data in the block `block`: every setting
// it uses is set here, so that panels of a multiplot do not inherit each other's.
std::string heatmap_plot(const Heatmap& m, int w, int h, const PixelBox& frame,
                         const std::string& block) {
  std::ostringstream s;
  s << "set title " << quote(m.title) << "\n";
  s << margins(w, h, frame);
  s << "set xrange [" << number(m.x_range.min) << ":" << number(m.x_range.max) << "]\n";
  s << "set yrange [" << number(m.y_range.min) << ":" << number(m.y_range.max) << "]\n";
  if (m.palette == Heatmap::Palette::Grey) {
    s << "set palette grey\nunset logscale cb\nset cbrange [0:1]\n";
  } else {
    // A viridis-like ramp: perceptually uniform, lightness rising monotonically (reads in grey).
    s << "set palette defined (0 '#440154', 0.13 '#482878', 0.25 '#3e4989', 0.38 '#31688e', "
         "0.5 '#26828e', 0.63 '#1f9e89', 0.75 '#35b779', 0.88 '#6ece58', 1 '#fde725')\n";
  }
  double lo = INFINITY, hi = 0;
  for (double v : m.values)
    if (v > 0 && std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
  // A log scale needs a value > 0 (an exact formula's error map is 0 everywhere: drawn linear).
  const bool log_values = m.log_values && lo <= hi;
  if (m.palette != Heatmap::Palette::Grey) {
    s << (lo <= hi || !m.log_values ? "set cbrange [*:*]\n" : "set cbrange [0:1]\n");
    s << (log_values ? "set logscale cb\n" : "unset logscale cb\n");
  }
  // The colour bar labels the values themselves: powers of ten on a log scale that spans a
  // decade or more; across less, where gnuplot would label none, five values spread evenly.
  if (log_values && hi < 10 * lo) {
    s << "set format cb '%.2g'\nset cbtics (";
    for (int k = 0; k < 5; ++k) s << (k ? ", " : "") << number(lo * std::pow(hi / lo, k / 4.0));
    s << ")\n";
  } else {
    s << "set format cb '" << (log_values ? "%.0e" : "%g") << "'\nset cbtics autofreq\n";
  }
  if (m.axes) {
    s << "set border lc rgb " << kBorder
      << "\nset xtics out\nset ytics out\nset cbtics out\nset colorbox\n";
    s << "set xlabel " << quote(m.x_label) << "\nset ylabel " << quote(m.y_label) << "\n";
    s << "set cblabel " << quote(m.value_label + (log_values ? " (log scale)" : ""))
      << " offset 1.5,0\n";
  } else {
    s << "unset tics\nunset colorbox\nunset border\nunset xlabel\nunset ylabel\nunset cblabel\n";
  }
  s << "unset key\n" << block << " << EOD\n";
  const double dx = (m.x_range.max - m.x_range.min) / m.nx;
  const double dy = (m.y_range.max - m.y_range.min) / m.ny;
  for (int j = 0; j < m.ny; ++j) {
    for (int i = 0; i < m.nx; ++i) {
      double v = m.values[static_cast<std::size_t>(j) * static_cast<std::size_t>(m.nx) +
                          static_cast<std::size_t>(i)];
      if (log_values && !(v > 0)) v = NAN;
      s << number(m.x_range.min + (i + 0.5) * dx) << " " << number(m.y_range.min + (j + 0.5) * dy)
        << " " << number(v) << "\n";
    }
    s << "\n";
  }
  s << "EOD\nplot " << block << " using 1:2:3 with image\n";
  return s.str();
}

// The frame of a heat map in a cell of the image (pixels): margins for its title and axes, or,
// without axes, the largest box of square cells that fits under the title (renderings keep
// their aspect).
PixelBox heatmap_frame(const Heatmap& m, const PixelBox& cell) {
  const int top = m.title.empty() ? kNoTitlePx : kTitlePx;
  if (!m.axes) {
    const double ratio = static_cast<double>(m.nx) / m.ny;
    const double avail_w = std::max(1, cell.width - 8),
                 avail_h = std::max(1, cell.height - top - 8);
    const double w = std::min(avail_w, avail_h * ratio), h = w / ratio;
    return {cell.left + static_cast<int>((cell.width - w) / 2), cell.top + top, static_cast<int>(w),
            static_cast<int>(h)};
  }
  return {cell.left + kLeftPx, cell.top + top, std::max(1, cell.width - kLeftPx - kColourBarPx),
          std::max(1, cell.height - top - kAxisBelowPx)};
}

}  // namespace

std::string gnuplot_script(const Heatmap& m, ImageFormat format, const std::string& output) {
  check_heatmap(m);
  return terminal(format, m.width, m.height) + "set output " + quote(output) + "\n" +
         heatmap_plot(m, m.width, m.height, heatmap_frame(m, {0, 0, m.width, m.height}), "$map");
}

std::string gnuplot_script(const HeatmapGrid& g, ImageFormat format, const std::string& output) {
  if (g.panels.empty()) throw Error("nothing to plot: the heat-map grid has no panels");
  if (g.columns < 1)
    throw Error("a heat-map grid needs at least one column, got " + std::to_string(g.columns));
  for (const Heatmap& m : g.panels) check_heatmap(m);
  const int columns = std::min<int>(g.columns, static_cast<int>(g.panels.size()));
  const int rows = (static_cast<int>(g.panels.size()) + columns - 1) / columns;
  const int top = g.title.empty() ? 0 : kTitlePx;
  const int cell_w = g.width / columns, cell_h = (g.height - top) / rows;
  std::ostringstream s;
  s << terminal(format, g.width, g.height) << "set output " << quote(output) << "\n";
  s << "set multiplot title " << quote(g.title) << "\n";
  for (std::size_t p = 0; p < g.panels.size(); ++p) {
    const int r = static_cast<int>(p) / columns, c = static_cast<int>(p) % columns;
    const PixelBox cell{c * cell_w, top + r * cell_h, cell_w, cell_h};
    s << heatmap_plot(g.panels[p], g.width, g.height, heatmap_frame(g.panels[p], cell),
                      "$map" + std::to_string(p));
  }
  s << "unset multiplot\n";
  return s.str();
}

PixelBox chart_frame(const Chart& chart) { return chart_layout(chart).frame; }

bool gnuplot_available() {
  static const bool found = std::system("gnuplot --version >/dev/null 2>&1") == 0;
  return found;
}

namespace {

void run_gnuplot(const std::string& script, const std::string& path) {
  if (!gnuplot_available()) {
    throw Error("gnuplot not found: install gnuplot-nox (scripts/install-deps does)",
                SourceLocation{path});
  }
  static std::atomic<int> counter{0};
  const auto dir = std::filesystem::temp_directory_path();
  const std::string stem =
      "shaderfit-plot-" + std::to_string(getpid()) + "-" + std::to_string(counter++);
  const auto script_path = dir / (stem + ".gp");
  const auto log_path = dir / (stem + ".log");
  {
    std::ofstream f(script_path);
    f << script;
    if (!f) throw Error("cannot write a temporary file in " + dir.string());
  }
  std::error_code ec;
  std::filesystem::remove(path, ec);
  const std::string cmd =
      "gnuplot '" + script_path.string() + "' >'" + log_path.string() + "' 2>&1";
  const int status = std::system(cmd.c_str());
  std::string log;
  {
    std::ifstream f(log_path);
    std::getline(f, log, '\0');
  }
  std::filesystem::remove(script_path, ec);
  std::filesystem::remove(log_path, ec);
  if (status != 0 || !std::filesystem::exists(path) || std::filesystem::file_size(path) == 0) {
    for (char& ch : log)
      if (ch == '\n') ch = ' ';
    throw Error("gnuplot could not draw '" + path +
                    "': " + (log.empty() ? "no output" : log.substr(0, 300)),
                SourceLocation{path});
  }
}

}  // namespace

void render(const Chart& chart, const std::string& path) {
  run_gnuplot(gnuplot_script(chart, image_format_for(path), path), path);
}

void render(const Heatmap& map, const std::string& path) {
  run_gnuplot(gnuplot_script(map, image_format_for(path), path), path);
}

void render(const HeatmapGrid& grid, const std::string& path) {
  run_gnuplot(gnuplot_script(grid, image_format_for(path), path), path);
}

}  // namespace shaderfit
