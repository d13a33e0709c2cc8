// The HTML report of a run's JSON (`shaderfit report`): a search's front with its plot, the
// comparison with baselines, curves and code; any other run's JSON laid out generically.
//
//   HtmlReport r("shaderfit search: run.json");
//   SearchReportOptions o;
//   o.data = &dataset;                                    // optional: scores and curves
//   o.baselines = {{"Schlick", "r0 + (1 - r0)*x^5", parse_formula_on("r0 + (1 - r0)*x^5",
//   dataset)}};
//   o.choice = parse_choice_rule("cost=6", {"ChoiceRule"});   // default: the knee of the front
//   add_search_report(r, run_json, "run.json", o);
//   r.write("run.html");
#pragma once

#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <vector>

#include "shaderfit/data/dataset.hpp"
#include "shaderfit/expr/expression.hpp"
#include "shaderfit/expr/precision.hpp"
#include "shaderfit/problem/problem.hpp"
#include "shaderfit/reference/function.hpp"
#include "shaderfit/report/html.hpp"
#include "shaderfit/search/front/choice.hpp"

namespace shaderfit {

struct ReportFormula {
  std::string label;
  std::string formula;    // as the user wrote it
  Expression expression;  // parsed over the data's columns
};

struct SearchReportOptions {
  // The data the search ran on: with it, the baselines and the chosen formula are scored, and
  // when the formula's inputs are those of a Fresnel sweep, curves over the angle are drawn.
  const Dataset* data = nullptr;
  // The function behind the data, when it is a reference (problem/problem.hpp): the chosen
  // formula's error is then also drawn, in one variable as a curve at the samples, in two as a
  // map over the whole domain.
  const reference::ReferenceFunction* reference = nullptr;
  // The problem behind `data`, when it is a scene (Problem::scene): the page then shows the
  // baselines' and the chosen formula's pictures and FLIP (report/scene_report.hpp), computed in
  // half too where the precision is half.
  const Problem* problem = nullptr;
  std::vector<ReportFormula> baselines;  // scored only with data; labels go in plot keys
  // The chosen formula, shown as code: the front member `choice` picks (search/choice.hpp; the
  // knee by default), or `formula` when not empty (any formula over the front's inputs).
  ChoiceRule choice;
  std::string formula;
  // Not empty: each figure is also written there as NAME.png and NAME.svg (front, curves,
  // error, error-map, curves-ior1.5, curves-aluminium), the directory created if missing.
  std::string figure_directory;
  // Per-material inputs (cost/per_material.hpp); empty: the run's ("uniform" in its JSON). With
  // any, costs are per pixel with the per-material count beside them, and the code is in two
  // parts.
  std::vector<std::string> uniform;
  // The arithmetic the baselines and the chosen formula are scored in (eval/evaluate_in.hpp);
  // unset: the run's ("precision" in its options), else double. The front's own columns are
  // the run's; a half column is shown where the run measured one.
  std::optional<Precision> precision;
};

// What the report chose, and how and why, in words (for a closing line on the command line).
struct ReportChoice {
  std::string formula, how, why;
  bool by_rule = true;  // false: SearchReportOptions::formula was shown
};

// Adds a search's sections: its data, settings and run, the front as a table and a plot, the
// chosen formula with how and why it was chosen, its comparison with the baselines, curves and
// its code in GLSL, HLSL and CUDA. Plot keys name the curves briefly ("reference", a baseline's
// label, "chosen (cost 5)"); the captions and tables give the formulas. `run` is the JSON
// search_json writes; `source` names it in errors. Throws shaderfit::Error for an empty front, a
// formula that does not parse (at SearchReportOptions::formula), or a figure that cannot be
// written.
ReportChoice add_search_report(HtmlReport& report, const nlohmann::json& run,
                               const std::string& source, const SearchReportOptions& options);

// Any run's JSON, generically: scalars as settings, arrays of objects as tables, PNG paths that
// exist as images, nested objects as sub-sections (under a heading `name` when not empty).
void add_json_section(HtmlReport& report, const nlohmann::json& j, const std::string& name,
                      int level);

}  // namespace shaderfit
