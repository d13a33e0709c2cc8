// shaderfit report: one self-contained HTML page for a run, from the JSON the run wrote
// (the layout is the library's, shaderfit/report/search_report.hpp). A search result (a "front"
// list) gets its front, plot, comparison with the baselines, curves and code; any other run's
// JSON (fit, lut, rational) is laid out generically.
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>

#include "cli.hpp"
#include "data_source.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/eval/dataset_eval.hpp"
#include "shaderfit/report/html.hpp"
#include "shaderfit/report/search_json.hpp"
#include "shaderfit/report/search_report.hpp"
#include "shaderfit/search/front/choice.hpp"

namespace shaderfit::cli {

namespace {

using nlohmann::json;

struct ReportArgs {
  std::string run_path, output, title, choose, figures;
  DataSource data;
  std::vector<std::string> baselines, uniform;
  std::string precision;  // empty: the run's
};

ReportChoice search_report(HtmlReport& r, const json& j, const ReportArgs& a) {
  SearchReportOptions o;
  // --choose: a rule (knee, cost=N, error=E) or a formula.
  if (is_choice_rule(a.choose))
    o.choice = parse_choice_rule(a.choose, {"ChoiceRule"});
  else
    o.formula = a.choose;
  o.figure_directory = a.figures;
  o.uniform = a.uniform;
  if (!a.precision.empty()) o.precision = precision_option(a.precision);
  // The data: as the options say, else as the run recorded it (a reference is sampled again).
  std::optional<Problem> problem;
  if (a.data.given())
    problem = load_problem(a.data);
  else if (j.contains("problem") && !j["problem"].is_null()) {
    // A CSV file that is no longer where the run read it leaves the page without curves.
    const ProblemSource recorded = problem_source_from_json(j["problem"], a.run_path);
    if (recorded.csv_path.empty() || std::filesystem::exists(recorded.csv_path))
      problem = shaderfit::load_problem(recorded);
  }
  if (problem) {
    const Dataset& d = problem->data;
    o.data = &d;
    o.reference = problem->reference.get();
    o.problem = &*problem;
    for (std::size_t i = 0; i < a.baselines.size(); ++i) {
      const auto eq = a.baselines[i].find('=');
      ReportFormula b;
      // A bare formula is keyed "baseline N" in plots; the formula is in the captions.
      b.label = eq == std::string::npos ? "baseline " + std::to_string(i + 1)
                                        : a.baselines[i].substr(0, eq);
      b.formula = eq == std::string::npos ? a.baselines[i] : a.baselines[i].substr(eq + 1);
      b.expression = parse_formula_on(b.formula, d, "--baseline " + std::to_string(i + 1));
      o.baselines.push_back(std::move(b));
    }
  }
  return add_search_report(r, j, a.run_path, o);
}

void run_report(ReportArgs& a, Context& ctx) {
  std::ifstream f(a.run_path);
  if (!f) throw Error("cannot open '" + a.run_path + "'", SourceLocation{a.run_path});
  json j;
  try {
    f >> j;
  } catch (const json::exception& e) {
    throw Error(std::string("not JSON: ") + e.what(), SourceLocation{a.run_path});
  }
  if (!j.is_object())
    throw Error("expected a JSON object written by a shaderfit run", SourceLocation{a.run_path});
  const bool search = j.contains("front");
  HtmlReport r(a.title.empty()
                   ? (search ? "shaderfit search" : "shaderfit run") + std::string(": ") +
                         std::filesystem::path(a.run_path).filename().string()
                   : a.title);
  std::optional<ReportChoice> chosen;
  if (search) {
    chosen = search_report(r, j, a);
  } else {
    add_json_section(r, j, "", 2);
  }
  r.write(a.output);
  ctx.out << "wrote " << a.output << "\n";
  if (chosen)
    ctx.out << chosen_formula_lines(chosen->formula, chosen->how, chosen->why, chosen->by_rule);
}

}  // namespace

void register_report_command(CLI::App& app, Context& ctx) {
  auto a = std::make_shared<ReportArgs>();
  CLI::App* cmd = app.add_subcommand(
      "report", "One self-contained HTML page for a run (search, fit, lut, rational)");
  cmd->add_option("run", a->run_path, "the JSON a run wrote (--json)")->required();
  cmd->add_option("-o,--output", a->output, "HTML file to write")->required();
  cmd->add_option("--title", a->title, "page title");
  add_uniform_option(cmd, a->uniform);
  add_precision_option(cmd, a->precision, "the baselines and the chosen formula are scored in",
                       "the run's");
  cmd->add_option("--choose", a->choose,
                  std::string(kChooseHelp) + ", or a formula to show instead");
  cmd->add_option("--figures", a->figures,
                  "also write each figure to this directory as NAME.png and NAME.svg");
  cmd->add_option("--baseline", a->baselines,
                  "formulas to compare with, 'Schlick=r0 + (1 - r0)*x^5' (needs data)")
      ->allow_extra_args(false);
  add_data_options(cmd, a->data, DataFiles | References | InputsTarget);
  cmd->footer(
      "Example:\n  shaderfit search --dataset fresnel-seed --inputs r0,x --target R --json "
      "run.json\n"
      "  shaderfit report run.json --dataset fresnel-seed --baseline 'Schlick=r0 + (1 - r0)*x^5' "
      "-o run.html");
  cmd->callback([a, &ctx] { run_report(*a, ctx); });
}

}  // namespace shaderfit::cli
