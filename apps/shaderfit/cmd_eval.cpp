// shaderfit eval: error metrics of formulas on a data set, overall and per group, against a
// baseline. The JSON schema is documented in docs/eval-json.md.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <ostream>

#include "data_source.hpp"
#include "cli.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/cost/per_material.hpp"
#include "shaderfit/eval/dataset_eval.hpp"
#include "shaderfit/eval/metrics.hpp"
#include "shaderfit/eval/evaluate_in.hpp"
#include "shaderfit/expr/precision.hpp"
#include "shaderfit/expr/print.hpp"
#include "shaderfit/report/command_json.hpp"
#include "shaderfit/verify/certify.hpp"
#include "shaderfit/verify/worst_case.hpp"

namespace shaderfit::cli {

namespace {

struct EvalArgs {
  DataSource data;
  std::vector<std::string> groups, uniform;
  bool groups_given = false;
  std::string baseline;
  std::vector<std::string> formulas;
  std::string json_path;
  std::string cost_target;  // --cost-target: empty unless given
  bool float32 = false;  // --float32: the same as --precision float
  std::string precision = "double";
  bool certify = false;
  double certify_time_s = CertifyOptions{}.time_limit_s;
  int digits = 0;
};

// --precision by name (--float32 picks float).
Precision precision_of(const EvalArgs& a) {
  return a.float32 ? Precision::Float : precision_option(a.precision);
}

// "x = 0.5" or "(x, y) = (0.5, 1)": a point of the reference's domain.
// The costs shown: --cost-target's, or sass with --uniform; none otherwise.
std::optional<InstructionTarget> cost_target_of(const EvalArgs& a) {
  if (!a.cost_target.empty()) return parse_instruction_target(a.cost_target, {"--cost-target"});
  if (!a.uniform.empty()) return InstructionTarget::Sass;
  return std::nullopt;
}

std::string point_text(const Problem& p, const std::vector<double>& point) {
  if (!p.reference || point.size() != p.reference->domain.size()) return "?";
  std::string names, values;
  for (std::size_t i = 0; i < point.size(); ++i) {
    names += (i ? ", " : "") + p.reference->domain[i].name;
    values += (i ? ", " : "") + format_number(point[i], PrintOptions::for_people());
  }
  return point.size() == 1 ? names + " = " + values : "(" + names + ") = (" + values + ")";
}

void print_table(std::ostream& out, const std::vector<EvalFormulaResult>& results,
                 const EvalArgs& a, const Problem& p) {
  const Dataset& d = p.data;
  out << fmt::format(
      "shaderfit eval: {}, target {}{}\n",
      p.reference ? p.description : fmt::format("{}, {} rows", p.description, d.rows()), p.target,
      precision_of(a) == Precision::Double ? ""
                                           : ", " + std::string(precision_name(precision_of(a))));
  out << problem_notes(p, "");
  const PrintOptions print = PrintOptions::for_people(a.digits);
  const EvalFormulaResult* base = results.front().baseline ? &results.front() : nullptr;
  int number = 0;
  for (const EvalFormulaResult& r : results) {
    out << '\n'
        << (r.baseline ? std::string("[baseline] ") : fmt::format("[{}] ", ++number))
        << to_infix(r.expression, print) << '\n';
    if (const std::optional<InstructionTarget> t = cost_target_of(a)) {
      const SplitCost c = split_instruction_count(r.expression, a.uniform, *t);
      if (a.uniform.empty())
        out << fmt::format("  cost: {} instructions ({})\n", c.per_pixel, instruction_target_name(*t));
      else
        out << fmt::format("  cost: {} per pixel, {} per material ({} instructions)\n", c.per_pixel,
                           c.per_material, instruction_target_name(*t));
    }
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
    if (r.checked_between_samples)
      out << fmt::format("  {:<28} max abs {:.4e} at {}, searched for between the samples too\n",
                         "", r.all.max_abs, point_text(p, r.worst_point));
    if (r.certified_max_abs)
      out << fmt::format("  {:<28} certified: |error| <= {:.4e} on the whole domain{} ({:.2g} s)\n",
                         "", *r.certified_max_abs,
                         r.certified_converged || std::isinf(*r.certified_max_abs)
                             ? ""
                             : " (the time ran out: a looser bound)",
                         r.certify_time_s);
    if (r.certified_max_abs && std::isinf(*r.certified_max_abs))
      out << fmt::format("  {:<28} no finite bound: {}\n", "", r.certify_note);
    for (std::size_t g = 0; g < r.groups.size(); ++g) {
      const EvalGroupResult& gm = r.groups[g];
      row(gm.column + "=" + gm.label, gm.metrics, compare ? &base->groups[g].metrics : nullptr);
    }
  }
}

EvalReport to_report(std::vector<EvalFormulaResult> results, const EvalArgs& a, const Problem& p) {
  return {p.description, p.data.rows(), p.target,          precision_of(a),
          a.groups,      a.uniform,     std::move(results), cost_target_of(a)};
}

// With a reference: the errors between the samples too, and a certified bound when asked.
void check_between_samples(EvalFormulaResult& r, const Problem& p, const EvalArgs& a) {
  WorstCaseOptions wo;
  wo.samples = a.data.problem.samples;
  const WorstCaseSearch w(*p.reference, r.expression.variables, wo);
  const WorstCase c = w.check(r.expression);
  // Between the samples the check computes float64 and float32; half takes float64's there.
  const bool float32 = precision_of(a) == Precision::Float;
  const double max_abs = float32 ? c.float32_max_abs : c.max_abs;
  if (max_abs >= r.all.max_abs) r.worst_point = c.worst_abs.point;
  r.all.max_abs = std::max(r.all.max_abs, max_abs);
  r.all.max_rel = std::max(r.all.max_rel, float32 ? c.float32_max_rel : c.max_rel);
  r.checked_between_samples = true;
  if (a.certify) {
    CertifyOptions co;
    co.time_limit_s = a.certify_time_s;
    const Certificate cert = certify(r.expression, r.expression.variables, *p.reference, co);
    r.certified_max_abs = cert.bound;
    r.certified_converged = cert.converged;
    r.certify_time_s = cert.time_s;
    r.certify_note = cert.note;
    // What the certification met is attained too (a pole between the samples blows up near
    // where it found no finite bound).
    const ErrorPoint met = w.certified_worst(r.expression, cert);
    if (!float32 && !(met.abs_error <= r.all.max_abs)) {
      r.all.max_abs = met.abs_error;
      r.worst_point = met.point;
    }
  }
}

void run_eval(EvalArgs& a, Context& ctx) {
  (void)PrintOptions::for_people(a.digits);  // a bad --digits stops here
  const Precision precision = precision_of(a);
  (void)cost_target_of(a);  // a bad --cost-target stops here, before the data is read
  const Problem p = load_problem(a.data);
  const Dataset& d = p.data;
  if (a.formulas.empty()) throw Error("no formula to evaluate", SourceLocation{"eval"});
  if (a.certify && !p.reference)
    throw Error(
        "a certified bound needs the function itself: give --reference or "
        "--reference-file with --domain",
        SourceLocation{"--certify"});
  const std::span<const double> target = d.numeric(p.target).values;
  // A built-in data set comes with its natural groups unless the user chose others.
  if (!a.groups_given && !a.data.problem.dataset.empty()) {
    for (const char* g : {"kind", "material"})
      if (d.find(g)) a.groups.push_back(g);
  }
  for (const std::string& g : a.groups) (void)d.column(g);
  // The formulas may read any numeric column but the target, or only the inputs given.
  const bool inputs_given = !a.data.inputs.empty();
  if (!a.uniform.empty()) {
    std::vector<std::string> inputs = p.inputs;
    if (!inputs_given) {
      inputs.clear();
      for (const std::string& n : d.names())
        if (n != p.target && d.column(n).numeric()) inputs.push_back(n);
    }
    check_uniform_inputs(a.uniform, inputs);
    check_uniform_in_groups(d, a.uniform, a.groups);
  }

  if (precision == Precision::Half) check_fits_half(target, "the target", {"--precision"});

  std::vector<EvalFormulaResult> results;
  if (!a.baseline.empty()) {
    results.push_back(
        evaluate_formula_on(a.baseline, "--baseline", d, target, a.groups, precision_of(a)));
    results.back().baseline = true;
  }
  for (std::size_t i = 0; i < a.formulas.size(); ++i) {
    results.push_back(evaluate_formula_on(a.formulas[i], "formula " + std::to_string(i + 1), d,
                                          target, a.groups, precision_of(a)));
  }
  if (inputs_given)
    for (std::size_t i = 0; i < results.size(); ++i) {
      // results[0] is the baseline when there is one; the formulas count from 1.
      const std::size_t number = a.baseline.empty() ? i + 1 : i;
      for (const std::string& v : results[i].expression.variables)
        if (std::find(p.inputs.begin(), p.inputs.end(), v) == p.inputs.end())
          throw Error("it reads '" + v + "', which is not one of the inputs given",
                      SourceLocation{results[i].baseline ? std::string("--baseline")
                                                         : "formula " + std::to_string(number)});
    }
  if (p.reference)
    for (EvalFormulaResult& r : results) check_between_samples(r, p, a);

  if (a.json_path == "-") {
    ctx.out << eval_json(to_report(std::move(results), a, p)) << '\n';
    return;
  }
  print_table(ctx.out, results, a, p);
  if (!a.json_path.empty()) {
    std::ofstream f(a.json_path);
    if (!f) throw Error("cannot write '" + a.json_path + "'", SourceLocation{"--json"});
    f << eval_json(to_report(std::move(results), a, p)) << '\n';
  }
}

}  // namespace

void register_eval_command(CLI::App& app, Context& ctx) {
  auto args = std::make_shared<EvalArgs>();
  CLI::App* cmd = app.add_subcommand(
      "eval", "Error metrics of formulas on a data set, per group, against a baseline");
  add_data_options(cmd, args->data, DataFiles | References | InputsTarget | SeedAlias);
  cmd->add_option("--group", args->groups,
                  "column(s) whose values split the rows into groups (repeat or comma-separate)")
      ->delimiter(',')
      ->allow_extra_args(false)
      ->each([args](const std::string&) { args->groups_given = true; });
  cmd->add_option("--baseline", args->baseline, "formula the others are compared with");
  add_uniform_option(cmd, args->uniform);
  cmd->add_option("--cost-target", args->cost_target,
                  "show each formula's instruction count on this target: sass, ptx, generic, "
                  "rdna2 or rdna3 (with --uniform: per pixel and per material; default sass there)");
  cmd->add_option("--json", args->json_path, "write the results as JSON to PATH ('-' for stdout)");
  add_precision_option(cmd, args->precision, "the formulas are computed in", "double");
  cmd->add_flag("--float32", args->float32, "the same as --precision float");
  cmd->add_flag("--certify", args->certify,
                "with a reference: a rigorous bound of each formula's error on the whole domain");
  cmd->add_option("--certify-time", args->certify_time_s,
                  "seconds per formula for the certified bound (default 10)");
  add_digits_option(cmd, args->digits);
  cmd->add_option("formulas", args->formulas,
                  "formulas over the data's column names, e.g. 'r0 + (x - r0)*x^4'");
  cmd->footer(
      "Example:\n  shaderfit eval --dataset fresnel-seed --seed 1 --target R \\\n"
      "    --baseline 'r0 + (1 - r0)*x^5' 'r0 + (x - r0)*x^4'");
  cmd->callback([args, &ctx] { run_eval(*args, ctx); });
}

}  // namespace shaderfit::cli
