// shaderfit fit: fit the named free parameters of a formula to data or to a reference function,
// globally, per group of the data, or per cell of a grid (docs/fit.md).
#include <fmt/format.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <ostream>

#include "cmd_fit_blocks.hpp"
#include "shaderfit/cli.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/eval/dataset_eval.hpp"
#include "shaderfit/eval/metrics.hpp"
#include "shaderfit/expr/print.hpp"

namespace shaderfit::cli {

namespace {

struct BlockReport {
  double mse = 0;                    // of the fitted formula, raw values, unweighted
  std::vector<double> baseline_mse;  // of each baseline on the same rows
};

std::vector<BlockReport> block_reports(const FitSetup& s, const FixedFormSummary& sum,
                                       const std::vector<std::string>& baselines) {
  std::vector<BlockReport> out(s.problem.blocks.size());
  std::map<const Dataset*, std::vector<std::vector<double>>> cache;  // baseline values per data set
  for (std::size_t b = 0; b < out.size(); ++b) {
    const FitBlock& blk = s.problem.blocks[b];
    const BlockSource& src = s.sources[b];
    Expression e = s.problem.formula;
    e.parameter_values = sum.blocks[b].parameters;
    std::vector<const double*> cols;
    for (const auto& c : blk.columns) cols.push_back(c.data());
    std::vector<double> v(blk.target.size());
    if (!v.empty()) evaluate(e, std::span<const double* const>(cols), std::span<double>(v));
    out[b].mse = error_metrics(v, blk.target).mse;
    auto& values = cache[src.data];
    if (values.empty())
      for (std::size_t k = 0; k < baselines.size(); ++k)
        values.push_back(evaluate_on(
            parse_formula_on(baselines[k], *src.data, "--baseline " + std::to_string(k + 1)),
            *src.data));
    for (const std::vector<double>& all : values) {
      std::vector<double> picked;
      for (std::size_t i : src.rows) picked.push_back(all[i]);
      out[b].baseline_mse.push_back(error_metrics(picked, src.target).mse);
    }
  }
  return out;
}

const char* fit_loss_description(Loss l) {
  return l == Loss::Mse   ? "least squares"
         : l == Loss::Log ? "log2 error (least squares)"
                          : "max error (minimax)";
}

nlohmann::json to_json(const FitSetup& s, const FixedFormSummary& sum,
                       const std::vector<BlockReport>& reports,
                       const std::vector<std::string>& baselines) {
  nlohmann::json j;
  j["schema"] = "shaderfit.fit/1";
  j["formula"] = to_infix(s.problem.formula);
  j["data"] = s.data_description;
  j["reference"] = s.reference_description;
  j["loss"] = fit_loss_description(s.options.loss);
  j["solver"] = sum.solver;
  j["linear"] = sum.linear;
  j["coupled"] = sum.coupled;
  j["seconds"] = sum.seconds;
  j["failed_blocks"] = sum.failed_blocks;
  j["parameters"] = nlohmann::json::array();
  for (std::size_t p = 0; p < sum.parameter_names.size(); ++p)
    j["parameters"].push_back(
        {{"name", sum.parameter_names[p]},
         {"scope", sum.scopes[p] == ParameterScope::global ? "global" : "per block"}});
  j["baselines"] = baselines;
  j["blocks"] = nlohmann::json::array();
  for (std::size_t b = 0; b < sum.blocks.size(); ++b) {
    const BlockResult& r = sum.blocks[b];
    nlohmann::json params;
    for (std::size_t p = 0; p < r.parameters.size(); ++p)
      params[sum.parameter_names[p]] = r.parameters[p];
    j["blocks"].push_back({{"label", r.label},
                           {"rows", r.rows},
                           {"ok", r.ok},
                           {"failure", r.failure},
                           {"parameters", params},
                           {"initial_cost", r.initial_cost},
                           {"final_cost", r.final_cost},
                           {"rms", r.rms},
                           {"max_abs", r.max_abs},
                           {"iterations", r.iterations},
                           {"termination", r.termination},
                           {"mse", reports[b].mse},
                           {"baseline_mse", reports[b].baseline_mse}});
  }
  return j;
}

std::string table_csv(const FixedFormSummary& sum, const std::vector<BlockReport>& reports) {
  std::string s = "block,rows,status";
  for (const std::string& p : sum.parameter_names) s += "," + p;
  s += ",cost,mse";
  if (!reports.empty())
    for (std::size_t k = 0; k < reports.front().baseline_mse.size(); ++k)
      s += fmt::format(",baseline{}_mse", k + 1);
  s += "\n";
  for (std::size_t b = 0; b < sum.blocks.size(); ++b) {
    const BlockResult& r = sum.blocks[b];
    std::string label = r.label, status = r.ok ? "ok" : "failed: " + r.failure;
    for (std::string* t : {&label, &status}) std::replace(t->begin(), t->end(), ',', ';');
    s += fmt::format("{},{},{}", label, r.rows, status);
    for (double v : r.parameters) s += "," + format_number(v);
    s += fmt::format(",{},{}", r.final_cost, reports[b].mse);
    for (double m : reports[b].baseline_mse) s += fmt::format(",{}", m);
    s += "\n";
  }
  return s;
}

void print_table(std::ostream& out, const FitSetup& s, const FixedFormSummary& sum,
                 const std::vector<BlockReport>& reports, const FitArgs& a) {
  out << fmt::format("shaderfit fit: {}\n", to_infix(s.problem.formula));
  out << fmt::format("  data: {}; reference: {}{}\n", s.data_description, s.reference_description,
                     s.grouping.empty() ? "" : "; " + s.grouping);
  if (s.dropped_rows)
    out << fmt::format("  {} rows outside the grid were left out\n", s.dropped_rows);
  out << fmt::format("  loss: {}\n  ", fit_loss_description(s.options.loss)) << sum.brief_report();
  for (std::size_t k = 0; k < a.baselines.size(); ++k)
    out << fmt::format("  baseline [{}]: {}\n", k + 1, a.baselines[k]);
  std::vector<std::size_t> shown;  // per-block parameters, or every parameter with one block
  for (std::size_t p = 0; p < sum.parameter_names.size(); ++p)
    if (sum.scopes[p] == ParameterScope::per_block || sum.blocks.size() == 1) shown.push_back(p);
  out << fmt::format("\n  {:<34} {:>7}", "block", "rows");
  for (std::size_t p : shown) out << fmt::format(" {:>12}", sum.parameter_names[p]);
  out << fmt::format(" {:>11}", "MSE");
  for (std::size_t k = 0; k < a.baselines.size(); ++k)
    out << fmt::format(" {:>11}", fmt::format("MSE [{}]", k + 1));
  out << "\n";
  for (std::size_t b = 0; b < sum.blocks.size() && b < a.max_rows; ++b) {
    const BlockResult& r = sum.blocks[b];
    out << fmt::format("  {:<34} {:>7}", r.label, r.rows);
    for (std::size_t p : shown) out << fmt::format(" {:>12.6g}", r.parameters[p]);
    if (!r.ok) {
      out << "  failed: " << r.failure << "\n";
      continue;
    }
    out << fmt::format(" {:>11.4e}", reports[b].mse);
    for (double m : reports[b].baseline_mse) out << fmt::format(" {:>11.4e}", m);
    out << "\n";
  }
  if (sum.blocks.size() > a.max_rows)
    out << fmt::format("  ... {} more blocks (--table PATH writes them all)\n",
                       sum.blocks.size() - a.max_rows);
}

void write_file(const std::string& path, const std::string& text, const char* option) {
  std::ofstream f(path);
  if (f) f << text;
  if (!f) throw Error("cannot write '" + path + "'", SourceLocation{option});
}

void run_fit(const FitArgs& a, Context& ctx) {
  const FitSetup s = make_fit_setup(a);
  FixedFormSummary sum;
  solve_fixed_form(s.options, s.problem, &sum);
  const std::vector<BlockReport> reports = block_reports(s, sum, a.baselines);
  if (!a.table_path.empty()) write_file(a.table_path, table_csv(sum, reports), "--table");
  if (a.json_path == "-") {
    ctx.out << to_json(s, sum, reports, a.baselines).dump(2) << '\n';
  } else {
    print_table(ctx.out, s, sum, reports, a);
    if (!a.json_path.empty())
      write_file(a.json_path, to_json(s, sum, reports, a.baselines).dump(2) + "\n", "--json");
  }
  if (sum.failed_blocks > 0)
    ctx.err << fmt::format("shaderfit: warning: {} of {} blocks failed (listed above)\n",
                           sum.failed_blocks, sum.blocks.size());
}

}  // namespace

void register_fit_command(CLI::App& app, Context& ctx) {
  auto a = std::make_shared<FitArgs>();
  CLI::App* cmd = app.add_subcommand(
      "fit", "Fit the free parameters of a formula, globally, per group or per grid cell");
  add_data_options(cmd, a->data, true);
  cmd->add_option("formula", a->formula, "the formula, e.g. 'r0 + (1 - r0 - s*cos_theta)*x^4'")
      ->required();
  cmd->add_option("--param", a->params,
                  "free parameter NAME or NAME=START (repeat or comma-separate)")
      ->delimiter(',')
      ->allow_extra_args(false);
  cmd->add_option("--target", a->target, "data column the formula approximates");
  cmd->add_option(
      "--reference", a->reference,
      "built-in reference function (see docs/fit.md) or a formula, instead of --target");
  cmd->add_option("--per-group", a->per_group,
                  "PARAM:COLUMN: one value of PARAM per value of COLUMN")
      ->delimiter(',')
      ->allow_extra_args(false);
  cmd->add_option("--per-cell", a->per_cell, "parameters with one value per grid cell")
      ->delimiter(',')
      ->allow_extra_args(false);
  cmd->add_option("--grid", a->grid,
                  "conditioning variable name=lo:hi:cells[:sqrt] (repeat per axis)")
      ->allow_extra_args(false);
  cmd->add_option("--domain", a->domain,
                  "sampled variable name=lo:hi:count[:midpoints|endpoints] (repeat)")
      ->allow_extra_args(false);
  cmd->add_option("--define", a->defines,
                  "derived column 'name = formula' over earlier names (repeat)")
      ->allow_extra_args(false);
  cmd->add_option("--random-samples", a->random_samples,
                  "sample each cell at N uniform random points instead of a grid");
  cmd->add_option("--rng-seed", a->rng_seed, "seed of the random sampling (default 1)");
  cmd->add_option("--weight", a->weight, "per-row weights: a column or a formula (>= 0)");
  cmd->add_option("--loss", a->loss, "ls (least squares), log (log2 error), max (minimax)");
  cmd->add_option(
      "--transform", a->transform,
      "fit T(formula) to T(reference), T over y and the variables, e.g. 'log2(y / f0)'");
  cmd->add_option("--solver", a->solver, "auto, linear or lm (Levenberg-Marquardt)");
  cmd->add_option("--constraint", a->constraints,
                  "'C = 0', 'f(x = 0) = f0', 'df/dx(x = 1) = 0' (repeat)")
      ->allow_extra_args(false);
  cmd->add_option("--baseline", a->baselines,
                  "formula compared per block (MSE), e.g. Schlick (repeat)")
      ->allow_extra_args(false);
  cmd->add_option("--max-iterations", a->max_iterations,
                  "Levenberg-Marquardt iterations (default 100)");
  cmd->add_option("--threads", a->threads, "threads for blocks in parallel (0: all cores)");
  cmd->add_option("--max-rows", a->max_rows, "blocks printed in the table (default 40)");
  cmd->add_option("--table", a->table_path, "write every block's parameters and errors as CSV");
  cmd->add_option("--json", a->json_path, "write the results as JSON to PATH ('-' for stdout)");
  cmd->footer(
      "Example (seed 001's shape parameter, one s per material):\n"
      "  shaderfit fit --dataset fresnel-seed --target R --param s=1 --per-group s:material \\\n"
      "    --baseline 'r0 + (1 - r0)*x^5' --baseline 'r0 + (x - r0)*x^4' 'r0 + (1 - r0 - "
      "s*cos_theta)*x^4'");
  cmd->callback([a, &ctx] { run_fit(*a, ctx); });
}

}  // namespace shaderfit::cli
