// Formulas judged in a problem's scene (problem/problem.hpp: Problem::scene): the picture each
// renders against the reference's, their FLIP map and figures, and the report's section that
// shows them (docs/scenes.md).
//
//   SceneImages im = formula_scene_images(problem, e);     // im.flip.mean, im.visible_share
//   add_scene_section(report, problem, {{"chosen", e}, {"Schlick", schlick}}, Precision::Half);
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "shaderfit/expr/expression.hpp"
#include "shaderfit/expr/precision.hpp"
#include "shaderfit/problem/problem.hpp"
#include "shaderfit/report/html.hpp"
#include "shaderfit/scene/scene.hpp"

namespace shaderfit {

// e at every sample of the scene, computed in `precision`, as the term of the picture; the
// reference's picture takes the problem's target. e's variables are the problem's columns or any
// scene quantity, by name. Throws Error located at "scene" when the problem has no scene, and at
// "formula" for a variable that is neither.
SceneImages formula_scene_images(const Problem& problem, const Expression& e,
                                 Precision precision = Precision::Double);

// Reference, approximation and FLIP map in one PNG (stacked top to bottom for wide scenes, else
// left to right).
void write_scene_png(const std::string& path, const SceneImages& images);

struct SceneFormula {
  std::string label;  // "chosen (cost 5)", "Schlick"
  Expression expression;
};

// A heading, and per formula: reference, approximation and FLIP map in one picture (stacked
// for wide scenes), with the mean FLIP, the share of pixels above kFlipVisible and the displayed
// pixels' RMSE; then a table of those figures. With `half` the same again for each formula
// computed in half precision. PNGs also go to `figure_directory` when it is not empty, as
// scene-N.png. `display_loss`: the search ranked by the display loss (said on the page).
void add_scene_section(HtmlReport& report, const Problem& problem,
                       const std::vector<SceneFormula>& formulas, bool half,
                       const std::string& figure_directory = "", bool display_loss = false);

}  // namespace shaderfit
