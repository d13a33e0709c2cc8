#include "shaderfit/report/scene_report.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>

#include "core/files.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/eval/evaluate_in.hpp"
#include "shaderfit/expr/print.hpp"
#include "shaderfit/image/flip.hpp"
#include "shaderfit/image/png.hpp"

namespace shaderfit {

SceneImages formula_scene_images(const Problem& problem, const Expression& e, Precision precision) {
  if (!problem.scene) throw Error("the problem has no scene", {"scene"});
  std::vector<const double*> columns;
  for (const std::string& v : e.variables) {
    const Column* c = problem.data.find(v);
    columns.push_back(c != nullptr && c->numeric() ? c->values.data()
                                                   : problem.scene->column(v, "formula").data());
  }
  std::vector<double> values(problem.scene->samples());
  evaluate_in(precision, e, columns, values);
  return scene_images(*problem.scene, problem.data.numeric(problem.target).values, values);
}

namespace {

// Reference, approximation and FLIP map in one RGB picture: stacked top to bottom when the scene
// is more than twice as wide as high, else left to right; 4 white pixels between them.
struct Strip {
  std::size_t width = 0, height = 0;
  std::vector<std::uint8_t> rgb;
  bool stacked = false;
};

Strip strip(const SceneImages& im) {
  const std::size_t w = static_cast<std::size_t>(im.reference.width);
  const std::size_t h = static_cast<std::size_t>(im.reference.height);
  constexpr std::size_t kGap = 4;
  Strip s;
  s.stacked = w > 2 * h;
  s.width = s.stacked ? w : 3 * w + 2 * kGap;
  s.height = s.stacked ? 3 * h + 2 * kGap : h;
  s.rgb.assign(s.width * s.height * 3, 255);
  const std::vector<std::uint8_t> parts[] = {image_bytes(im.reference),
                                             image_bytes(im.approximation), flip_colormap(im.flip)};
  for (std::size_t k = 0; k < 3; ++k) {
    const std::size_t x0 = s.stacked ? 0 : k * (w + kGap), y0 = s.stacked ? k * (h + kGap) : 0;
    for (std::size_t y = 0; y < h; ++y)
      for (std::size_t x = 0; x < w; ++x)
        for (std::size_t c = 0; c < 3; ++c)
          s.rgb[((y0 + y) * s.width + x0 + x) * 3 + c] = parts[k][(y * w + x) * 3 + c];
  }
  return s;
}

}  // namespace

void write_scene_png(const std::string& path, const SceneImages& images) {
  const Strip s = strip(images);
  write_png(path, s.width, s.height, s.rgb);
}

namespace {

std::string png_path(const std::string& directory, int n) {
  if (!directory.empty()) {
    make_directories(directory);
    return (std::filesystem::path(directory) / fmt::format("scene-{}.png", n)).string();
  }
  static std::atomic<int> counter{0};  // unique across threads (a batch's pages)
  return (std::filesystem::temp_directory_path() /
          fmt::format("shaderfit-scene-{}-{}-{}.png", getpid(), n, counter++))
      .string();
}

}  // namespace

void add_scene_section(HtmlReport& report, const Problem& problem,
                       const std::vector<SceneFormula>& formulas, bool half,
                       const std::string& figure_directory, bool display_loss) {
  if (!problem.scene) throw Error("the problem has no scene", {"scene"});
  const SceneSpec& spec = problem.scene->spec;
  report.heading("In the picture");
  report.paragraph(fmt::format(
      "The {} scene ({} x {} pixels, {} shading samples): the function stands for the factor {} "
      "of the specular term; the pictures differ only there. Displayed after exposure {:g}, the "
      "ACES filmic tonemap and sRGB encoding. FLIP is LDR-FLIP (Andersson et al. 2020) at {:.0f} "
      "pixels per degree; visible: the share of pixels with FLIP above {:g}.{}",
      scene_kind_name(spec.kind), problem.scene->width, problem.scene->height,
      problem.scene->samples(), shading_term_name(*spec.term), spec.exposure,
      FlipOptions{}.pixels_per_degree, kFlipVisible,
      !display_loss ? ""
                    : " The search's loss was the display loss: its MSE weighs each "
                      "sample by its pixel's squared display slope (docs/scenes.md)."));
  std::vector<std::vector<std::string>> rows;
  int n = 0;
  for (const Precision precision : half ? std::vector<Precision>{Precision::Double, Precision::Half}
                                        : std::vector<Precision>{Precision::Double}) {
    for (const SceneFormula& f : formulas) {
      const SceneImages im = formula_scene_images(problem, f.expression, precision);
      const Strip s = strip(im);
      const std::string path = png_path(figure_directory, ++n);
      write_png(path, s.width, s.height, s.rgb);
      const std::string in = precision == Precision::Half ? ", computed in half" : "";
      report.image(path, fmt::format("{}{}: {} reference, approximation, FLIP map (black 0, "
                                     "yellow 1). Mean FLIP {:.4f}, visible {:.2f}%.",
                                     f.label, in, s.stacked ? "top to bottom:" : "left to right:",
                                     im.flip.mean, 100 * im.visible_share));
      if (figure_directory.empty()) std::filesystem::remove(path);
      rows.push_back(
          {f.label + in, to_infix(f.expression, PrintOptions::for_people()),
           fmt::format("{:.4f}", im.flip.mean), fmt::format("{:.2f}%", 100 * im.visible_share),
           fmt::format("{:.4g}", im.display_rmse), fmt::format("{:.4g}", im.display_max)});
    }
  }
  report.table({"", "formula", "mean FLIP", "visible", "display RMSE", "display max"}, rows,
               {false, false, true, true, true, true});
}

}  // namespace shaderfit
