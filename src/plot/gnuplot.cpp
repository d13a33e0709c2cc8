// Chart and heat-map rendering through gnuplot. The whole program, data included, is one script
// (inline data blocks), so what is rendered can be saved and re-run by hand.
#include <unistd.h>

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

void check_range(const std::optional<Range>& r, const char* axis) {
  if (r && !(r->min < r->max)) {
    throw Error(std::string(axis) + " range has min >= max (" + number(r->min) + " >= " + number(r->max) + ")",
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
  if (c.series.empty() && c.markers.empty()) throw Error("nothing to plot: the chart has no series");
  check_range(c.x_range, "x");
  check_range(c.y_range, "y");
  std::ostringstream s;
  s << terminal(format, c.width, c.height) << "set output " << quote(output) << "\n";
  if (!c.title.empty()) s << "set title " << quote(c.title) << "\n";
  s << "set xlabel " << quote(c.x_label) << "\nset ylabel " << quote(c.y_label) << "\n";
  s << "set grid lc rgb '#d9d9d9' lw 0.6\nset border lc rgb '#404040'\n";
  s << "set key outside right top vertical Left reverse samplen 3 spacing 1.2\n";
  if (c.log_x) s << "set logscale x\nset format x '10^{%L}'\nset format x '%g'\n";
  if (c.log_y) s << "set logscale y\nset format y '%g'\n";
  if (c.x_range) s << "set xrange [" << number(c.x_range->min) << ":" << number(c.x_range->max) << "]\n";
  if (c.y_range) s << "set yrange [" << number(c.y_range->min) << ":" << number(c.y_range->max) << "]\n";
  bool any_positive_y = false;
  for (std::size_t i = 0; i < c.series.size(); ++i) {
    const Series& sr = c.series[i];
    if (sr.x.size() != sr.y.size()) {
      throw Error("series '" + sr.label + "' has " + std::to_string(sr.x.size()) + " x values and " +
                  std::to_string(sr.y.size()) + " y values");
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
    s << " lw " << width << " lc rgb '" << kColours[k] << "' dt " << kDashes[k] << " pt " << kPoints[k];
    if (sr.style != Series::Style::Points) s << " ps 1.1";
    s << " title " << quote(sr.label);
  }
  s << "\n";
  return s.str();
}

std::string gnuplot_script(const Heatmap& m, ImageFormat format, const std::string& output) {
  if (m.nx <= 0 || m.ny <= 0) throw Error("heat map has no cells");
  if (m.values.size() != static_cast<std::size_t>(m.nx) * static_cast<std::size_t>(m.ny)) {
    throw Error("heat map values (" + std::to_string(m.values.size()) + ") don't fill its " +
                std::to_string(m.nx) + " x " + std::to_string(m.ny) + " grid");
  }
  check_range(m.x_range, "x");
  check_range(m.y_range, "y");
  std::ostringstream s;
  s << terminal(format, m.width, m.height) << "set output " << quote(output) << "\n";
  if (!m.title.empty()) s << "set title " << quote(m.title) << "\n";
  s << "set xlabel " << quote(m.x_label) << "\nset ylabel " << quote(m.y_label) << "\n";
  s << "set cblabel " << quote(m.value_label + (m.log_values ? " (log10)" : "")) << "\n";
  s << "set xrange [" << number(m.x_range.min) << ":" << number(m.x_range.max) << "]\n";
  s << "set yrange [" << number(m.y_range.min) << ":" << number(m.y_range.max) << "]\n";
  if (m.palette == Heatmap::Palette::Grey) {
    s << "set palette grey\nset cbrange [0:1]\n";
  } else {
    // A viridis-like ramp: perceptually uniform, lightness rising monotonically (reads in grey).
    s << "set palette defined (0 '#440154', 0.13 '#482878', 0.25 '#3e4989', 0.38 '#31688e', "
         "0.5 '#26828e', 0.63 '#1f9e89', 0.75 '#35b779', 0.88 '#6ece58', 1 '#fde725')\n";
  }
  if (m.axes) {
    s << "set tics out\n";
  } else {
    s << "unset tics\nunset colorbox\nunset border\nunset xlabel\nunset ylabel\nset size ratio -1\n";
  }
  s << "unset key\n$map << EOD\n";
  const double dx = (m.x_range.max - m.x_range.min) / m.nx;
  const double dy = (m.y_range.max - m.y_range.min) / m.ny;
  for (int j = 0; j < m.ny; ++j) {
    for (int i = 0; i < m.nx; ++i) {
      double v = m.values[static_cast<std::size_t>(j) * static_cast<std::size_t>(m.nx) + static_cast<std::size_t>(i)];
      if (m.log_values) v = v > 0 ? std::log10(v) : NAN;
      s << number(m.x_range.min + (i + 0.5) * dx) << " " << number(m.y_range.min + (j + 0.5) * dy) << " "
        << number(v) << "\n";
    }
    s << "\n";
  }
  s << "EOD\nplot $map using 1:2:3 with image\n";
  return s.str();
}

bool gnuplot_available() {
  static const bool found = std::system("gnuplot --version >/dev/null 2>&1") == 0;
  return found;
}

namespace {

void run_gnuplot(const std::string& script, const std::string& path) {
  if (!gnuplot_available()) {
    throw Error("gnuplot not found: install gnuplot-nox (scripts/install-deps does)", SourceLocation{path});
  }
  static std::atomic<int> counter{0};
  const auto dir = std::filesystem::temp_directory_path();
  const std::string stem = "shaderfit-plot-" + std::to_string(getpid()) + "-" + std::to_string(counter++);
  const auto script_path = dir / (stem + ".gp");
  const auto log_path = dir / (stem + ".log");
  {
    std::ofstream f(script_path);
    f << script;
    if (!f) throw Error("cannot write a temporary file in " + dir.string());
  }
  std::error_code ec;
  std::filesystem::remove(path, ec);
  const std::string cmd = "gnuplot '" + script_path.string() + "' >'" + log_path.string() + "' 2>&1";
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
    throw Error("gnuplot could not draw '" + path + "': " + (log.empty() ? "no output" : log.substr(0, 300)),
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

}  // namespace shaderfit
