// shaderfit eval: error metrics of formulas on a data set, overall and per group, against a
// baseline. The JSON schema is documented in docs/eval-json.md.
#include <fmt/format.h>

#include <fstream>
#include <ostream>

#include "data_source.hpp"
#include "shaderfit/cli.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/eval/dataset_eval.hpp"
#include "shaderfit/eval/metrics.hpp"
#include "shaderfit/expr/print.hpp"
#include "shaderfit/report/command_json.hpp"

namespace shaderfit::cli {

namespace {

struct EvalArgs {
  DataSource data;
  std::string target;
  std::vector<std::string> groups;
  bool groups_given = false;
  std::string baseline;
  std::vector<std::string> formulas;
  std::string json_path;
  bool float32 = false;
  int digits = 0;
};

void print_table(std::ostream& out, const std::vector<EvalFormulaResult>& results,
                 const EvalArgs& a, const Dataset& d) {
  out << fmt::format("shaderfit eval: {}, {} rows, target {}{}\n", a.data.describe(), d.rows(),
                     a.target, a.float32 ? ", float32" : "");
  const PrintOptions print = PrintOptions::for_people(a.digits);
  const EvalFormulaResult* base = results.front().baseline ? &results.front() : nullptr;
  int number = 0;
  for (const EvalFormulaResult& r : results) {
    out << '\n'
        << (r.baseline ? std::string("[baseline] ") : fmt::format("[{}] ", ++number))
        << to_infix(r.expression, print) << '\n';
    out << fmt::format("  {:<28} {:>6} {:>11} {:>11} {:>11} {:>11}{}\n", "group", "rows", "MSE",
                       "RMSE", "max abs", "max rel",
                       base && !r.baseline ? "  MSE vs baseline" : "");
    auto row = [&](const std::string& name, const ErrorMetrics& m, const ErrorMetrics* b) {
      std::string change;
      if (b) change = fmt::format("  {:>+15.1f}%", 100.0 * relative_change(m.mse, b->mse));
      out << fmt::format("  {:<28} {:>6} {:>11.4e} {:>11.4e} {:>11.4e} {:>11.4e}{}\n", name, m.rows,
                         m.mse, m.rmse, m.max_abs, m.max_rel, change);
      if (m.nonfinite)
        out << fmt::format("  {:<28} {} rows are NaN or infinite\n", "", m.nonfinite);
    };
    const bool compare = base && !r.baseline;
    row("all", r.all, compare ? &base->all : nullptr);
    for (std::size_t g = 0; g < r.groups.size(); ++g) {
      const EvalGroupResult& gm = r.groups[g];
      row(gm.column + "=" + gm.label, gm.metrics, compare ? &base->groups[g].metrics : nullptr);
    }
  }
}

EvalReport to_report(std::vector<EvalFormulaResult> results, const EvalArgs& a, const Dataset& d) {
  return {a.data.describe(), d.rows(), a.target, a.float32, a.groups, std::move(results)};
}

void run_eval(EvalArgs& a, Context& ctx) {
  (void)PrintOptions::for_people(a.digits);  // a bad --digits stops here
  Dataset d = load_data(a.data);
  if (a.formulas.empty()) throw Error("no formula to evaluate", SourceLocation{"eval"});
  const std::span<const double> target = d.numeric(a.target).values;
  // A built-in data set comes with its natural groups unless the user chose others.
  if (!a.groups_given && !a.data.dataset.empty()) {
    for (const char* g : {"kind", "material"})
      if (d.find(g)) a.groups.push_back(g);
  }
  for (const std::string& g : a.groups) (void)d.column(g);

  std::vector<EvalFormulaResult> results;
  if (!a.baseline.empty()) {
    results.push_back(
        evaluate_formula_on(a.baseline, "--baseline", d, target, a.groups, a.float32));
    results.back().baseline = true;
  }
  for (std::size_t i = 0; i < a.formulas.size(); ++i) {
    results.push_back(evaluate_formula_on(a.formulas[i], "formula " + std::to_string(i + 1), d,
                                          target, a.groups, a.float32));
  }

  if (a.json_path == "-") {
    ctx.out << eval_json(to_report(std::move(results), a, d)) << '\n';
    return;
  }
  print_table(ctx.out, results, a, d);
  if (!a.json_path.empty()) {
    std::ofstream f(a.json_path);
    if (!f) throw Error("cannot write '" + a.json_path + "'", SourceLocation{"--json"});
    f << eval_json(to_report(std::move(results), a, d)) << '\n';
  }
}

}  // namespace

void register_eval_command(CLI::App& app, Context& ctx) {
  auto args = std::make_shared<EvalArgs>();
  CLI::App* cmd = app.add_subcommand(
      "eval", "Error metrics of formulas on a data set, per group, against a baseline");
  add_data_options(cmd, args->data, true);
  cmd->add_option("--target", args->target, "column the formulas approximate")->required();
  cmd->add_option("--group", args->groups,
                  "column(s) whose values split the rows into groups (repeat or comma-separate)")
      ->delimiter(',')
      ->allow_extra_args(false)
      ->each([args](const std::string&) { args->groups_given = true; });
  cmd->add_option("--baseline", args->baseline, "formula the others are compared with");
  cmd->add_option("--json", args->json_path, "write the results as JSON to PATH ('-' for stdout)");
  cmd->add_flag("--float32", args->float32, "evaluate in float32, as a shader would");
  add_digits_option(cmd, args->digits);
  cmd->add_option("formulas", args->formulas,
                  "formulas over the data's column names, e.g. 'r0 + (x - r0)*x^4'");
  cmd->footer(
      "Example:\n  shaderfit eval --dataset fresnel-seed --seed 1 --target R \\\n"
      "    --baseline 'r0 + (1 - r0)*x^5' 'r0 + (x - r0)*x^4'");
  cmd->callback([args, &ctx] { run_eval(*args, ctx); });
}

}  // namespace shaderfit::cli
