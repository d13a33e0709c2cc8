// shaderfit fit: fit the named free parameters of a formula to data or to a reference function,
// globally, per group of the data, or per cell of a grid (docs/fit.md).
#include <fmt/format.h>

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <memory>
#include <ostream>

#include "cli.hpp"
#include "data_source.hpp"
#include "progress_bar.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/expr/print.hpp"
#include "shaderfit/fit/fit_setup.hpp"
#include "shaderfit/reference/language.hpp"
#include "shaderfit/report/command_json.hpp"

namespace shaderfit::cli {

namespace {

struct FitArgs {
  DataSource data;
  std::string formula;
  std::vector<std::string> params;     // NAME or NAME=START
  std::vector<std::string> per_group;  // NAME:COLUMN
  std::vector<std::string> per_cell;   // NAME
  std::vector<std::string> grid;       // name=lo:hi:cells[:sqrt]
  std::vector<std::string> domain;     // name=lo:hi[:count[:midpoints|endpoints]]
  std::vector<std::string> defines;    // name = formula
  std::size_t samples = 0;
  std::size_t random_samples = 0;
  std::uint64_t rng_seed = 1;
  std::string target, reference, reference_file, function, weight, transform;
  std::string loss = "ls", solver = "auto";
  std::vector<std::string> constraints, baselines;
  std::string json_path, table_path;
  std::size_t max_rows = 40;
  int max_iterations = 100;
  int threads = 0;
  int digits = 0;
};

[[noreturn]] void fail(const std::string& message, const char* option) {
  throw Error(message, SourceLocation{option});
}

// The library's FitSetup from the flags: where the data comes from, and the loss and solver by
// name.
FitSetup to_setup(const FitArgs& a) {
  const bool generated = !a.domain.empty();
  const bool has_data = a.data.given();
  if (generated && has_data)
    fail("give either --domain (sampled data) or --data/--dataset, not both", "--domain");
  if (!generated && !has_data)
    fail("no data: give --data FILE.csv, --dataset NAME or --domain", "--data");
  FitSetup s;
  if (has_data) {
    // The rows only: the formula names its columns, and the reference is fit's own.
    DataSource rows = a.data;
    rows.inputs.clear();
    rows.problem.drop_nonfinite = false;
    Problem p = load_problem(rows);
    s.data = std::move(p.data);
    s.data_name = p.description;
  }
  s.inputs = input_names(a.data);
  s.drop_nonfinite = a.data.problem.drop_nonfinite;
  s.domain = a.domain;
  s.samples = a.samples;
  s.random_samples = a.random_samples;
  s.rng_seed = a.rng_seed;
  s.grid = a.grid;
  s.definitions = a.defines;
  s.formula = a.formula;
  s.parameters = a.params;
  s.per_group = a.per_group;
  s.per_cell = a.per_cell;
  s.target = a.target;
  s.reference = a.reference;
  if (!a.reference_file.empty()) {
    s.reference_source = reference::read_shader_file(a.reference_file);
    s.reference_path = a.reference_file;
    if (a.function.empty())
      fail("name the function of the reference file to fit (--function NAME)", "--function");
  } else if (!a.function.empty()) {
    fail("--function names a function of --reference-file, which is not given", "--function");
  }
  s.function = a.function;
  s.weight = a.weight;
  s.transform = a.transform;
  s.constraints = a.constraints;
  s.baselines = a.baselines;
  FixedFormOptions& o = s.options;
  if (a.loss == "ls" || a.loss == "squared")
    o.loss = Loss::Mse;
  else if (a.loss == "log")
    o.loss = Loss::Log;
  else if (a.loss == "max")
    o.loss = Loss::MaxAbs;
  else
    fail("unknown loss '" + a.loss + "' (ls, log, max)", "--loss");
  const std::optional<SolverKind> solver = solver_kind_from_name(a.solver);
  if (!solver) fail("unknown solver '" + a.solver + "' (auto, linear, lm)", "--solver");
  o.solver = *solver;
  o.max_iterations = a.max_iterations;
  o.threads = a.threads;
  return s;
}

std::string table_csv(const FixedFormSummary& sum, const std::vector<BlockComparison>& reports) {
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

void print_table(std::ostream& out, const PreparedFit& s, const FixedFormSummary& sum,
                 const std::vector<BlockComparison>& reports, const FitArgs& a) {
  const PrintOptions print = PrintOptions::for_people(a.digits);
  PrintOptions named = print;  // the formula as given: parameters by name
  named.substitute_parameters = false;
  out << fmt::format("shaderfit fit: {}\n", to_infix(s.problem.formula, named));
  out << fmt::format("  data: {}; reference: {}{}\n", s.data_description, s.reference_description,
                     s.grouping.empty() ? "" : "; " + s.grouping);
  if (s.dropped_rows)
    out << fmt::format("  {} rows outside the grid were left out\n", s.dropped_rows);
  if (s.dropped_nonfinite)
    out << fmt::format("  {} rows where the reference is NaN or infinite were left out\n",
                       s.dropped_nonfinite);
  out << fmt::format("  loss: {}\n  ", loss_description(s.options.loss)) << sum.brief_report(print);
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
    for (std::size_t p : shown)
      out << fmt::format(" {:>12}", format_number(r.parameters[p], print));
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
  (void)PrintOptions::for_people(a.digits);  // a bad --digits stops here, before the fit
  const PreparedFit s = prepare_fit(to_setup(a));
  FixedFormSummary sum;
  ProgressBar bar(ctx, "fit");
  FixedFormOptions options = s.options;
  options.on_progress = bar.callback();
  solve_fixed_form(options, s.problem, &sum);
  bar.clear();
  const std::vector<BlockComparison> reports = compare_blocks(s, sum);
  if (!a.table_path.empty()) write_file(a.table_path, table_csv(sum, reports), "--table");
  if (a.json_path == "-") {
    ctx.out << fit_json(s, sum, reports) << '\n';
  } else {
    print_table(ctx.out, s, sum, reports, a);
    if (!a.json_path.empty()) write_file(a.json_path, fit_json(s, sum, reports) + "\n", "--json");
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
  add_data_options(cmd, a->data, DataFiles | SeedAlias | Inputs | NonFinite);
  cmd->add_option("formula", a->formula, "the formula, e.g. 'r0 + (1 - r0 - s*cos_theta)*x^4'")
      ->required();
  cmd->add_option("--param", a->params,
                  "free parameter NAME or NAME=START (repeat or comma-separate)")
      ->delimiter(',')
      ->allow_extra_args(false);
  cmd->add_option("--target", a->target, "data column the formula approximates");
  cmd->add_option("--reference", a->reference,
                  "the function to fit to, instead of --target: a formula over the columns in the "
                  "reference language (acos, erf, atan2, the built-ins: docs/reference.md), or a "
                  "built-in's name (fv-exact; docs/fit.md)");
  cmd->add_option("--reference-file", a->reference_file,
                  "the function to fit to as a GLSL or HLSL function in this file (with "
                  "--function); its parameters are columns");
  cmd->add_option("--function", a->function, "the function of --reference-file");
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
                  "sampled variable name=lo:hi (the default design) or "
                  "name=lo:hi:count[:midpoints|endpoints] (a regular grid); repeat")
      ->allow_extra_args(false);
  cmd->add_option("--samples", a->samples,
                  "points of the domain's default design (default: 10,001 in one variable; "
                  "docs/reference.md)");
  cmd->add_option("--define", a->defines,
                  "derived column 'name = formula' (reference language) over earlier names "
                  "(repeat)")
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
  add_digits_option(cmd, a->digits);
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
