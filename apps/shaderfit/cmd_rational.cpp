// shaderfit rational: Schlick's kernel-conditions method and minimax fits (docs/rational.md).
#include <fmt/format.h>

#include <algorithm>
#include <fstream>
#include <memory>
#include <ostream>

#include "shaderfit/cli.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/expr/print.hpp"
#include "shaderfit/rational/parametric.hpp"
#include "shaderfit/rational/setup.hpp"
#include "shaderfit/report/command_json.hpp"

namespace shaderfit::cli {

namespace {

using namespace shaderfit::rational;

struct RationalArgs {
  std::string target, var = "x", domain, fit = "none", rank = "rmse", json_path;
  std::vector<std::string> conds, forms, transforms, params;
  int count = 0;
  bool minimax = false, relative = false, list_targets = false;
};

RationalSetup to_setup(const RationalArgs& a) {
  RationalSetup s;
  s.target = a.target;
  s.variable = a.var;
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

void run_rational(const RationalArgs& a, Context& ctx) {
  if (a.list_targets) {
    for (const std::string& t : Target::builtin_target_names()) ctx.out << t << '\n';
    return;
  }
  PreparedRational prepared = prepare_rational(to_setup(a));
  RationalProblem& problem = prepared.problem;
  const RationalOptions& options = prepared.options;
  const std::vector<std::string>& names = problem.parameter_names;
  const int sweep = prepared.sweep;
  const std::vector<double>& values = prepared.sweep_values;
  const std::string& var = problem.target.variable();

  RationalReport report;
  report.target = problem.target.name();
  report.variable = var;
  report.domain = problem.domain;
  report.fit = a.minimax ? "minimax" : a.fit;
  for (const Condition& c : problem.conditions) report.conditions.push_back(c.text);
  report.parameter_names = names;
  const bool to_stdout = a.json_path == "-";
  std::vector<RationalForm> forms;
  for (double v : values) {
    if (sweep >= 0) problem.parameter_values[static_cast<std::size_t>(sweep)] = v;
    RationalSummary summary;
    solve(options, problem, &summary);
    for (std::size_t i = 0; i < problem.forms.size(); ++i)
      for (const FormResult& r : summary.results)
        if (r.form == problem.forms[i] && r.status == FormStatus::PoleInDomain)
          throw Error("form " + r.form.name(var) + ": " + r.message,
                      {"--form", static_cast<int>(i / prepared.transform_count) + 1, 1});
    if (summary.results.empty() || !summary.results.front().usable()) {
      const FormResult& r = summary.results.front();
      if (!problem.forms.empty())
        throw Error(fmt::format("form {} is {}: {}", r.form.name(var), form_status_name(r.status),
                                r.message),
                    {"--form"});
    }
    if (forms.empty())
      for (const FormResult& r : summary.results) forms.push_back(r.form);
    report.runs.push_back({problem.parameter_values, summary});
    if (to_stdout) continue;
    std::string head =
        fmt::format("shaderfit rational: {} on {} in [{}, {}]", problem.target.name(), var,
                    format_number(problem.domain.lo), format_number(problem.domain.hi));
    for (std::size_t i = 0; i < names.size(); ++i)
      head += fmt::format("{} {} = {}", i ? "," : ";", names[i],
                          format_number(problem.parameter_values[i]));
    ctx.out << head << '\n';
    for (const Condition& c : problem.conditions) ctx.out << "  condition: " << c.text << '\n';
    ctx.out << summary.full_report() << summary.brief_report() << "\n\n";
  }
  if (sweep >= 0) {
    const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
    if (*lo < *hi) {
      const std::string& pname = names[static_cast<std::size_t>(sweep)];
      report.laws = parametric_laws(options, problem, pname, {*lo, *hi}, forms);
      if (!to_stdout)
        ctx.out << "coefficients as functions of " << pname << " on [" << format_number(*lo) << ", "
                << format_number(*hi) << "]:\n";
      for (const ParametricLaw& l : report.laws) {
        if (to_stdout) continue;
        ctx.out << "  " << l.form.name(var) << ": ";
        if (!l.usable)
          ctx.out << "not usable over the range (" << l.note << ")\n";
        else if (l.all_rational)
          ctx.out << "rational in " << pname << ": " << l.formula << '\n';
        else {
          std::string missing;
          for (const CoefficientLaw& c : l.coefficients)
            if (!c.found) missing += (missing.empty() ? "" : ", ") + c.coefficient;
          ctx.out << "not rational in " << pname << " (" << missing << ")\n";
        }
        if (l.usable)
          for (const CoefficientLaw& c : l.coefficients)
            if (c.found && c.law != "0")
              ctx.out << "      " << c.coefficient << " = " << c.law << '\n';
      }
    }
  }
  if (to_stdout) {
    ctx.out << rational_json(report) << '\n';
  } else if (!a.json_path.empty()) {
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
                  "built-in function (--list-targets) or a formula in --var");
  cmd->add_option("--var", args->var, "the variable of a formula target (default x)");
  cmd->add_option("--domain", args->domain, "LO,HI (default: the target's natural domain, or 0,1)");
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
  cmd->add_option("--json", args->json_path, "write the results as JSON to PATH ('-' for stdout)");
  cmd->add_flag("--list-targets", args->list_targets, "list the built-in targets");
  cmd->footer(
      "Examples:\n"
      "  shaderfit rational --target fresnel-dielectric-f0 --param F0=0.04,0.5 --form 5/0 "
      "--transform '1 - cos' \\\n"
      "    --cond 'f(0)=1' --cond 'f(1)=F0' --cond \"f'(1)=0\" --cond \"f''(1)=0\" --cond "
      "\"f'''(1)=0\" --cond 'f^(4)(1)=0'\n"
      "  shaderfit rational --target exp --domain -1,1 --form 2/2 --minimax");
  cmd->callback([args, &ctx] { run_rational(*args, ctx); });
}

}  // namespace shaderfit::cli
