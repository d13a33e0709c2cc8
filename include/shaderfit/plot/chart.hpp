// Charts and heat maps, rendered to SVG or PNG by gnuplot run as a child process.
//
//   Chart c;
//   c.title = "Aluminium (n = 1.373 + 7.618i at 633 nm)";
//   c.x_label = "angle of incidence θ [degrees]";
//   c.y_label = "reflectance R";
//   c.series.push_back({"exact Fresnel", theta, r_exact});
//   c.series.push_back({"Schlick", theta, r_schlick});
//   render(c, "aluminium.png");            // the format follows the extension (.png or .svg)
//
// Layout: the plot frame has fixed margins in pixels (room for tic labels, axis labels and the
// title) and the key sits in a band under it, in up to 4 rows of columns; labels too long for
// their column are cut with "…", so long labels never squeeze the frame. Keep labels short
// ("reference", "Schlick", "chosen (cost 5)") and put formulas in a caption or a table. At the
// default size the frame covers at least 55% of the image whatever the labels (chart_frame).
//
// Colours come from the Okabe-Ito palette (distinguishable with the common colour-vision
// deficiencies) and each series also gets its own dash pattern and point shape, so the plot reads
// in greyscale. Heat maps use a perceptually uniform palette that is monotone in lightness.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace shaderfit {

struct Series {
  std::string label;
  std::vector<double> x, y;
  enum class Style { Lines, Points, LinesPoints } style = Style::Lines;
  bool emphasis = false;  // drawn thicker (the reference, or a chosen formula)
};

// A labelled point, e.g. a well-known formula on a Pareto front.
struct Marker {
  std::string label;
  double x = 0, y = 0;
};

struct Range {
  double min = 0, max = 1;
};

struct Chart {
  std::string title, x_label, y_label;
  std::vector<Series> series;
  std::vector<Marker> markers;
  bool log_x = false, log_y = false;
  std::optional<Range> x_range, y_range;
  bool step_series = false;  // draw Lines series as steps (a Pareto front is a staircase)
  int width = 900, height = 560;
};

// A heat map: the colour bar beside it shows the value scale (logarithmic with log_values) under
// value_label; give the axis labels and value_label their units.
struct Heatmap {
  std::string title, x_label, y_label, value_label;
  int nx = 0, ny = 0;
  std::vector<double> values;  // row-major, ny rows of nx values; row 0 at y_range.min
  Range x_range, y_range;      // the extent of the grid (cell edges)
  bool log_values = false;     // logarithmic colour scale; non-positive cells are drawn blank
  enum class Palette { Viridis, Grey } palette = Palette::Viridis;
  bool axes = true;  // false: an image with no tics or colour box (renderings)
  int width = 760, height = 640;
};

// Heat maps side by side in one image, `columns` to a row, each with its own title, axes and
// colour bar (the panels' width and height are not used), under a common title.
struct HeatmapGrid {
  std::string title;
  std::vector<Heatmap> panels;
  int columns = 2;
  int width = 1100, height = 900;
};

// The plot frame of a chart in pixels from the image's top left corner: what is left after the
// margins for the title, the tic and axis labels, and the key's band.
struct PixelBox {
  int left = 0, top = 0, width = 0, height = 0;
};
PixelBox chart_frame(const Chart& chart);

enum class ImageFormat { Png, Svg };

// The format for a path ending in .png or .svg. Throws shaderfit::Error for anything else.
ImageFormat image_format_for(const std::string& path);

// The gnuplot program for a chart or heat map, data inline: what render() runs. Throws
// shaderfit::Error for an empty chart, series with x and y of different lengths, a range with
// min >= max, a log axis with non-positive values only, or a heat map whose values don't fill it.
std::string gnuplot_script(const Chart& chart, ImageFormat format, const std::string& output);
std::string gnuplot_script(const Heatmap& map, ImageFormat format, const std::string& output);
// Throws as for each panel, and for a grid with no panels or columns < 1.
std::string gnuplot_script(const HeatmapGrid& grid, ImageFormat format, const std::string& output);

// Writes the image at `path`. Throws shaderfit::Error when gnuplot is missing ("gnuplot not
// found: install gnuplot-nox (scripts/install-deps does)"), fails, or writes nothing.
void render(const Chart& chart, const std::string& path);
void render(const Heatmap& map, const std::string& path);
void render(const HeatmapGrid& grid, const std::string& path);

// Whether gnuplot can be run here.
bool gnuplot_available();

}  // namespace shaderfit
