// Files of an FV bake: textures, error tables and images, shader code, JSON summary.
#include "shaderfit/lut/fv_output.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/files.hpp"
#include "fv_internal.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/image/dds.hpp"
#include "shaderfit/image/exr.hpp"
#include "shaderfit/image/png.hpp"

namespace shaderfit::lut {

namespace {

using Metric = double CellError::*;
// The four error panels, in order: the metric, its name in fv_summary.json, and for the
// labelled maps a title and the colour bar's label.
struct Panel {
  Metric metric;
  const char* name;
  const char* title;
  const char* value;
};
constexpr std::array<Panel, 4> kPanels = {{
    {&CellError::mean_log2, "mean_log2", "mean log2 error per cell",
     "mean |log2(FV / reference)| [stops]"},
    {&CellError::max_log2, "max_log2", "max log2 error per cell",
     "max |log2(FV / reference)| [stops]"},
    {&CellError::mean_abs, "mean_abs", "mean absolute error per cell", "mean |FV - reference|"},
    {&CellError::max_abs, "max_abs", "max absolute error per cell", "max |FV - reference|"},
}};

struct Range {
  double lo = 0, hi = 0;
};

Range panel_range(const FvTable& t, Metric m) {
  Range r{INFINITY, 0};
  for (std::size_t k = 0; k < t.cells.size(); ++k) {
    const double v = t.errors[k].*m;
    if (!t.cells[k].ok || !(v > 0) || !std::isfinite(v)) continue;
    r.lo = std::min(r.lo, v);
    r.hi = std::max(r.hi, v);
  }
  if (!(r.lo <= r.hi)) r = {0, 0};
  return r;
}

// A dark-to-bright ramp (black, purple, red, orange, pale yellow) for t in [0, 1].
std::array<std::uint8_t, 3> ramp(double t) {
  static constexpr double kStops[5][3] = {
      {0, 0, 4}, {87, 16, 110}, {188, 55, 84}, {249, 142, 9}, {252, 255, 164}};
  t = std::clamp(t, 0.0, 1.0) * 4;
  const auto k = std::min<std::size_t>(static_cast<std::size_t>(t), 3);
  const double f = t - static_cast<double>(k);
  std::array<std::uint8_t, 3> c{};
  for (int ch = 0; ch < 3; ++ch)
    c[ch] = static_cast<std::uint8_t>(
        std::lround(kStops[k][ch] + f * (kStops[k + 1][ch] - kStops[k][ch])));
  return c;
}

void write_text(const std::string& path, const std::string& text) {
  std::ofstream f(path, std::ios::binary);
  if (f) f << text;
  if (!f) throw Error("cannot write '" + path + "'", SourceLocation{path});
}

}  // namespace

std::string fv_error_csv(const FvTable& t) {
  std::string s =
      "i,j,roughness,f0,status,A,B,C,P0,P1,P2,max_abs,mean_abs,max_log2,mean_log2,max_log2_f16,"
      "mean_log2_f16\n";
  for (std::size_t k = 0; k < t.cells.size(); ++k) {
    const std::size_t i = k % t.size, j = k / t.size;
    const FvCell& c = t.cells[k];
    const CellError& e = t.errors[k];
    const CellError& h = t.errors_half[k];
    const float* p = &t.texels[4 * k];
    std::string status = c.ok ? "ok" : "failed: " + c.failure;
    std::replace(status.begin(), status.end(), ',', ';');
    s += fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n", i, j,
                     cell_roughness(i, t.size), cell_f0(j, t.size), status, c.a, c.b, c.c, p[0],
                     p[1], p[2], e.max_abs, e.mean_abs, e.max_log2, e.mean_log2, h.max_log2,
                     h.mean_log2);
  }
  return s;
}

std::vector<std::uint8_t> fv_error_image(const FvTable& t, std::size_t* width,
                                         std::size_t* height) {
  const std::size_t n = t.size, scale = std::max<std::size_t>(1, (128 + n - 1) / n),
                    panel = n * scale, gap = 4;
  *width = 4 * panel + 3 * gap;
  *height = panel;
  std::vector<std::uint8_t> rgb(*width * *height * 3, 255);
  for (std::size_t p = 0; p < kPanels.size(); ++p) {
    const Range r = panel_range(t, kPanels[p].metric);
    const double span = r.hi > r.lo ? std::log10(r.hi / r.lo) : 1.0;
    for (std::size_t y = 0; y < panel; ++y)
      for (std::size_t x = 0; x < panel; ++x) {
        const std::size_t k = (y / scale) * n + x / scale;
        std::array<std::uint8_t, 3> c = {255, 0, 255};  // failed
        if (t.cells[k].ok) {
          const double v = t.errors[k].*kPanels[p].metric;
          c = ramp(v > 0 && r.lo > 0 ? std::log10(v / r.lo) / span : 0.0);
        }
        std::uint8_t* px = &rgb[3 * (y * *width + p * (panel + gap) + x)];
        std::copy(c.begin(), c.end(), px);
      }
  }
  return rgb;
}

HeatmapGrid fv_error_maps(const FvTable& t) {
  HeatmapGrid g;
  g.title = "FV lookup table '" + std::string(variant_name(t.variant)) + "', " +
            std::to_string(t.size) + " x " + std::to_string(t.size) +
            " cells: error against the reference (failed cells blank)";
  g.columns = 2;
  for (const Panel& p : kPanels) {
    Heatmap m;
    m.title = p.title;
    m.x_label = "roughness (perceptual, alpha = roughness^2)";
    m.y_label = "sqrt(F0)";
    m.value_label = p.value;
    m.nx = m.ny = static_cast<int>(t.size);
    m.x_range = {0, 1};
    m.y_range = {0, 1};
    m.log_values = true;
    for (std::size_t k = 0; k < t.cells.size(); ++k)
      m.values.push_back(t.cells[k].ok ? t.errors[k].*p.metric : NAN);
    g.panels.push_back(std::move(m));
  }
  return g;
}

std::string fv_summary_json(const FvBake& bake, const FvLutOptions& o) {
  nlohmann::json j;
  j["schema"] = "shaderfit.lut/1";
  j["reference"] = bake.reference;
  j["size"] = o.size;
  j["fit_samples"] = o.fit_samples;
  j["eval_samples"] = o.eval_samples;
  j["clamp"] = {{"degrees_at_roughness_0", o.clamp_degrees},
                {"roughness_at_90_degrees", o.clamp_roughness}};
  j["endpoint_adjustment"] = {{"form", "s(r) = c0 + c1 u + c2 u^2 + c3 u^3, u = sqrt(roughness)"},
                              {"c", bake.adjustment.c}};
  j["bake_seconds"] = bake.seconds;
  j["variants"] = nlohmann::json::array();
  auto summary = [](const ErrorSummary& s) {
    return nlohmann::json{{"mean_log2", s.mean_log2},
                          {"max_log2", s.max_log2},
                          {"mean_abs", s.mean_abs},
                          {"max_abs", s.max_abs}};
  };
  for (const FvTable& t : bake.tables) {
    nlohmann::json v;
    v["name"] = variant_name(t.variant);
    v["constrained"] = variant_is_constrained(t.variant);
    v["float32"] = summary(t.summary);
    v["float16"] = summary(t.summary_half);
    v["f0_deviation"] = {{"float32", t.f0_deviation}, {"float16", t.f0_deviation_half}};
    v["seconds"] = t.seconds;
    v["failed_cells"] = t.failures;
    nlohmann::json scales;
    for (std::size_t p = 0; p < kPanels.size(); ++p) {
      const Range r = panel_range(t, kPanels[p].metric);
      scales[kPanels[p].name] = {r.lo, r.hi};
    }
    v["image_scales"] = scales;
    j["variants"].push_back(v);
  }
  return j.dump(2) + "\n";
}

std::vector<std::string> write_fv_bake(const FvBake& bake, const FvLutOptions& o,
                                       const std::string& directory) {
  make_directories(directory);
  std::vector<std::string> files;
  auto path = [&](const std::string& name) {
    files.push_back((std::filesystem::path(directory) / name).string());
    return files.back();
  };
  for (const FvTable& t : bake.tables) {
    const std::string v(variant_name(t.variant));
    write_dds(path("fv_" + v + "_rgba32f.dds"), t.size, t.size, t.texels, DdsFormat::rgba32f);
    write_dds(path("fv_" + v + "_rgba16f.dds"), t.size, t.size, t.texels_half, DdsFormat::rgba16f);
    write_exr(path("fv_" + v + ".exr"), t.size, t.size, t.texels,
              {{"shaderfit.variant", v},
               {"shaderfit.layout",
                "RGBA = (P0, P1, P2, valid), FV = exp2((P0 d + P1) d + P2), d = dot(L,H)"},
               {"shaderfit.axes", "x: roughness (i + 0.5) / size, y: sqrt(F0) (j + 0.5) / size"},
               {"shaderfit.reference", bake.reference}});
    write_text(path("fv_" + v + "_errors.csv"), fv_error_csv(t));
    if (gnuplot_available()) {
      render(fv_error_maps(t), path("fv_" + v + "_errors.png"));
    } else {
      std::size_t w = 0, h = 0;
      const std::vector<std::uint8_t> img = fv_error_image(t, &w, &h);
      write_png(path("fv_" + v + "_errors.png"), w, h, img);
    }
  }
  write_text(path("fv_lut.hlsl"), fv_hlsl(bake, o));
  write_text(path("fv_lut.glsl"), fv_glsl(bake, o));
  write_text(path("fv_summary.json"), fv_summary_json(bake, o));
  return files;
}

}  // namespace shaderfit::lut
