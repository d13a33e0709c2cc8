// shaderfit rational: Schlick's kernel-conditions method and minimax fits (docs/rational.md).
#include <fmt/format.h>

#include <algorithm>
#include <fstream>
#include <memory>
#include <ostream>

#include "cli.hpp"
#include "data_source.hpp"
#include "progress_bar.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/expr/print.hpp"
#include "shaderfit/rational/parametric.hpp"
#include "shaderfit/rational/rational_setup.hpp"
#include "shaderfit/reference/language.hpp"
#include "shaderfit/report/command_json.hpp"

namespace shaderfit::cli {

namespace {

using namespace shaderfit::rational;

struct RationalArgs {
  std::string target, var = "x", reference_file, function, domain, fit = "none", rank = "rmse",
                      json_path;
  std::vector<std::string> conds, forms, transforms, params;
  int count = 0;
  int digits = 0;
  bool minimax = false, relative = false, list_targets = false;
};

RationalSetup to_setup(const RationalArgs& a) {
  RationalSetup s;
  s.target = a.target;
  s.variable = a.var;
  if (!a.reference_file.empty()) {
    s.reference_source = reference::read_shader_file(a.reference_file);
    s.reference_path = a.reference_file;
  }
  s.function = a.function;
  s.domain = a.domain;
  s.conditions = a.conds;
  s.forms = a.forms;
  s.transforms = a.transforms;
  s.parameters = a.params;
  s.count = a.count;
  if (a.minimax || a.fit == "minimax")
    s.fit = Fit::Minimax;
  else if (a.fit == "lsq")
    s.fit = Fit::LeastSquares;
  else if (a.fit != "none")
    throw Error("unknown fit '" + a.fit + "' (none, lsq, minimax)", {"--fit"});
  s.relative_minimax = a.relative;
  if (a.rank == "max-abs")
    s.rank_by = Loss::MaxAbs;
  else if (a.rank == "max-rel")
    s.rank_by = Loss::MaxRel;
  else if (a.rank != "rmse")
    throw Error("unknown ranking '" + a.rank + "' (rmse, max-abs, max-rel)", {"--rank"});
  return s;
}

// The runs and the laws as text, each run under a heading with its parameter values.
void print_report(std::ostream& out, const RationalReport& report, const PrintOptions& print) {
  const std::string& var = report.variable;
  for (const RationalRun& run : report.runs) {
    std::string head =
        fmt::format("shaderfit rational: {} on {} in [{}, {}]", report.target, var,
                    format_number(report.domain.lo), format_number(report.domain.hi));
    for (std::size_t i = 0; i < report.parameter_names.size(); ++i)
      head += fmt::format("{} {} = {}", i ? "," : ";", report.parameter_names[i],
                          format_number(run.parameter_values[i], print));
    out << head << '\n';
    for (const std::string& c : report.conditions) out << "  condition: " << c << '\n';
    out << run.summary.full_report(print) << run.summary.brief_report(print) << "\n\n";
  }
  if (report.swept_parameter.empty()) return;
  const std::string& pname = report.swept_parameter;
  out << "coefficients as functions of " << pname << " on [" << format_number(report.sweep_range.lo)
      << ", " << format_number(report.sweep_range.hi) << "]:\n";
  for (const ParametricLaw& l : report.laws) {
    out << "  " << l.form.name(var) << ": ";
    if (!l.usable) {
      out << "not usable over the range (" << l.note << ")\n";
    } else if (l.all_rational) {
      out << "rational in " << pname << ": " << to_infix(l.expression, print) << '\n';
    } else {
      std::string missing;
      for (const CoefficientLaw& c : l.coefficients)
        if (!c.found) missing += (missing.empty() ? "" : ", ") + c.coefficient;
      out << "not rational in " << pname << " (" << missing << ")\n";
    }
    if (l.usable)
      for (const CoefficientLaw& c : l.coefficients)
        if (c.found && c.law != "0")
          out << "      " << c.coefficient << " = " << to_infix(c.expression, print) << '\n';
  }
}

void run_rational(const RationalArgs& a, Context& ctx) {
  if (a.list_targets) {
    for (const std::string& t : Target::builtin_target_names()) ctx.out << t << '\n';
    return;
  }
  const PrintOptions print = PrintOptions::for_people(a.digits);
  PreparedRational prepared = prepare_rational(to_setup(a));
  ProgressBar bar(ctx, "rational");
  prepared.options.on_progress = bar.callback();
  const RationalReport report = solve_prepared(prepared);
  bar.clear();
  if (a.json_path == "-") {
    ctx.out << rational_json(report) << '\n';
    return;
  }
  print_report(ctx.out, report, print);
  if (!a.json_path.empty()) {
    std::ofstream f(a.json_path);
    if (!f) throw Error("cannot write '" + a.json_path + "'", {"--json"});
    f << rational_json(report) << '\n';
  }
}

}  // namespace

void register_rational_command(CLI::App& app, Context& ctx) {
  auto args = std::make_shared<RationalArgs>();
  CLI::App* cmd = app.add_subcommand(
      "rational",
      "Rational approximations from kernel conditions (Schlick 1994), and minimax fits");
  cmd->add_option("--target", args->target,
                  "built-in function (--list-targets) or a formula in --var in the reference "
                  "language: acos(x), erf(x), atan2(x, 1), ... (docs/reference.md)");
  cmd->add_option("--var", args->var,
                  "the variable of a formula target (default x), or of a shader function");
  cmd->add_option("--reference-file", args->reference_file,
                  "the target as a GLSL or HLSL function in this file (with --function): its one "
                  "parameter, or the one without a --param value, is the variable");
  cmd->add_option("--function", args->function, "the function of --reference-file");
  cmd->add_option("--domain", args->domain,
                  "LO,HI or x=LO:HI (default: the target's natural domain, or 0,1)");
  cmd->add_option("--cond", args->conds,
                  "condition: f(a)=v, f'(a)=v, f^(k)(a)=v, int(a,b)=v; v a formula in the "
                  "parameters or 'ref'")
      ->allow_extra_args(false);
  cmd->add_option("--count", args->count, "enumerate every form m/n with this many coefficients");
  cmd->add_option("--form", args->forms, "a form m/n (numerator/denominator degree); repeatable")
      ->allow_extra_args(false);
  cmd->add_option("--transform", args->transforms,
                  "variable of the forms, affine in --var (e.g. '1 - x'); repeatable")
      ->allow_extra_args(false);
  cmd->add_option("--fit", args->fit, "coefficients beyond the conditions: none, lsq or minimax");
  cmd->add_flag("--minimax", args->minimax,
                "same as --fit minimax (Remez exchange; conditions kept exact)");
  cmd->add_flag("--relative", args->relative, "minimax of the relative error");
  cmd->add_option("--param", args->params, "NAME=V1[,V2...]: a parameter's value(s); one may sweep")
      ->allow_extra_args(false);
  cmd->add_option("--rank", args->rank, "rank forms by rmse, max-abs or max-rel");
  add_digits_option(cmd, args->digits);
  cmd->add_option("--json", args->json_path, "write the results as JSON to PATH ('-' for stdout)");
  cmd->add_flag("--list-targets", args->list_targets, "list the built-in targets");
  cmd->footer(
      "Examples:\n"
      "  shaderfit rational --target fresnel-dielectric-f0 --param F0=0.04,0.5 --form 5/0 "
      "--transform '1 - cos' \\\n"
      "    --cond 'f(0)=1' --cond 'f(1)=F0' --cond \"f'(1)=0\" --cond \"f''(1)=0\" --cond "
      "\"f'''(1)=0\" --cond 'f^(4)(1)=0'\n"
      "  shaderfit rational --target exp --domain -1,1 --form 2/2 --minimax\n"
      "  shaderfit rational --target 'erf(x)' --domain x=0:3 --form 3/3 --minimax");
  cmd->callback([args, &ctx] { run_rational(*args, ctx); });
}

}  // namespace shaderfit::cli
