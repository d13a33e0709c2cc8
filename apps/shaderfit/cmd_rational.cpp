// shaderfit rational: Schlick's kernel-conditions method and minimax fits (docs/rational.md).
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <ostream>

#include "shaderfit/cli.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/expr/print.hpp"
#include "shaderfit/rational/parametric.hpp"
#include "shaderfit/rational/solve.hpp"

namespace shaderfit::cli {

namespace {

using namespace shaderfit::rational;

struct RationalArgs {
  std::string target, var = "x", domain, fit = "none", rank = "rmse", json_path;
  std::vector<std::string> conds, forms, transforms, params;
  int count = 0;
  bool minimax = false, relative = false, list_targets = false;
};

struct Param {
  std::string name;
  std::vector<double> values;
};

// A constant formula ("0.5", "pi/2"), located at `where` + `offset` on error.
double constant(const std::string& text, const SourceLocation& where, int offset) {
  ParseOptions po;
  po.source = where.source;
  po.line = where.line > 0 ? where.line : 1;
  try {
    const Expression e = parse_formula(text, po);
    if (!e.variables.empty())
      throw Error("expected a number, not '" + e.variables.front() + "'",
                  {where.source, po.line, offset + 1});
    const double v = evaluate_scalar(e, {});
    if (!std::isfinite(v))
      throw Error("'" + text + "' is not a finite number", {where.source, po.line, offset + 1});
    return v;
  } catch (const Error& e) {
    if (e.where().column == 0 || e.where().column > static_cast<int>(text.size()) + 1) throw;
    throw Error(e.message(), {where.source, po.line, e.where().column + offset});
  }
}

std::vector<std::string> split_commas(const std::string& s) {
  std::vector<std::string> out(1);
  int depth = 0;
  for (char c : s) {
    depth += c == '(' ? 1 : (c == ')' ? -1 : 0);
    if (c == ',' && depth == 0)
      out.emplace_back();
    else
      out.back() += c;
  }
  return out;
}

// NAME=V1,V2,...
Param parse_param(const std::string& text, int index) {
  const SourceLocation where{"--param", index, 0};
  const auto eq = text.find('=');
  Param p;
  p.name = text.substr(0, eq);
  while (!p.name.empty() && p.name.back() == ' ') p.name.pop_back();
  if (eq == std::string::npos || p.name.empty())
    throw Error("expected NAME=VALUE[,VALUE...] in '" + text + "'", {"--param", index, 1});
  int offset = static_cast<int>(eq) + 1;
  for (const std::string& v : split_commas(text.substr(eq + 1))) {
    p.values.push_back(constant(v, where, offset));
    offset += static_cast<int>(v.size()) + 1;
  }
  return p;
}

Interval parse_domain(std::string text) {
  std::erase_if(text, [](char c) { return c == '[' || c == ']'; });
  const auto parts = split_commas(text);
  if (parts.size() != 2) throw Error("expected LO,HI in '" + text + "'", {"--domain", 1, 1});
  const Interval d{constant(parts[0], {"--domain", 1, 0}, 0),
                   constant(parts[1], {"--domain", 1, 0}, static_cast<int>(parts[0].size()) + 1)};
  if (!(d.lo < d.hi))
    throw Error("the domain's lower end must be below its upper end", {"--domain", 1, 1});
  return d;
}

nlohmann::json result_json(const FormResult& r, const std::string& var) {
  nlohmann::json j = {{"form", r.form.name(var)},
                      {"numerator_degree", r.form.numerator_degree},
                      {"denominator_degree", r.form.denominator_degree},
                      {"variable", r.form.variable.text(var)},
                      {"status", form_status_name(r.status)},
                      {"message", r.message},
                      {"condition_number", r.condition_number}};
  if (r.usable()) {
    j["rmse"] = r.rmse;
    j["max_abs"] = r.max_abs;
    j["max_rel"] = r.max_rel;
    j["cost"] = r.cost;
    j["formula"] = r.formula;
    j["numerator"] = r.rational.p;
    j["denominator"] = r.rational.q;
  }
  if (r.minimax) {
    const Equioscillation& e = *r.minimax;
    j["minimax"] = {
        {"levelled_error", e.levelled_error}, {"max_error", e.max_error}, {"spread", e.spread},
        {"iterations", e.iterations},         {"converged", e.converged}, {"relative", e.relative},
        {"symmetric", e.symmetric},           {"points", e.points},       {"errors", e.errors}};
  }
  return j;
}

void run_rational(const RationalArgs& a, Context& ctx) {
  if (a.list_targets) {
    for (const std::string& t : Target::builtin_target_names()) ctx.out << t << '\n';
    return;
  }
  if (a.target.empty())
    throw Error("--target is required (a built-in name or a formula)", {"--target"});
  // Parameters: at most one may take several values (a sweep).
  std::vector<Param> params;
  for (std::size_t i = 0; i < a.params.size(); ++i)
    params.push_back(parse_param(a.params[i], static_cast<int>(i) + 1));
  std::vector<std::string> names;
  int sweep = -1;
  for (std::size_t i = 0; i < params.size(); ++i) {
    if (std::find(names.begin(), names.end(), params[i].name) != names.end())
      throw Error("parameter " + params[i].name + " given twice",
                  {"--param", static_cast<int>(i) + 1, 1});
    names.push_back(params[i].name);
    if (params[i].values.size() > 1) {
      if (sweep >= 0)
        throw Error("only one parameter may take several values",
                    {"--param", static_cast<int>(i) + 1, 1});
      sweep = static_cast<int>(i);
    }
  }
  RationalProblem problem;
  // A bare name that is not the variable means a built-in: report it as an unknown target.
  const bool bare = a.target != a.var && std::all_of(a.target.begin(), a.target.end(), [](char c) {
                      return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
                    });
  problem.target = bare ? Target::builtin(a.target) : Target::formula(a.target, a.var, names);
  problem.parameter_names = names;
  for (const Param& p : params) problem.parameter_values.push_back(p.values.front());
  problem.domain = a.domain.empty() ? problem.target.natural_domain() : parse_domain(a.domain);
  for (std::size_t i = 0; i < a.conds.size(); ++i)
    problem.conditions.push_back(
        parse_condition(a.conds[i], names, {"--cond", static_cast<int>(i) + 1, 0}));
  const std::string& var = problem.target.variable();
  if (a.count > 0 && !a.forms.empty()) throw Error("use --count or --form, not both", {"--count"});
  // Explicit forms, in each --transform (or in the variable itself).
  std::vector<Transform> transforms;
  for (const std::string& t : a.transforms) transforms.push_back(Transform::parse(t, var));
  for (std::size_t i = 0; i < a.forms.size(); ++i) {
    RationalForm f = parse_form(a.forms[i]);
    for (const Transform& t :
         transforms.empty() ? std::vector<Transform>{Transform::identity()} : transforms) {
      f.variable = t;
      problem.forms.push_back(f);
    }
  }
  RationalOptions options;
  options.coefficient_count = a.count;
  options.transforms = transforms;
  if (a.minimax || a.fit == "minimax")
    options.fit = Fit::Minimax;
  else if (a.fit == "lsq")
    options.fit = Fit::LeastSquares;
  else if (a.fit != "none")
    throw Error("unknown fit '" + a.fit + "' (none, lsq, minimax)", {"--fit"});
  options.relative_minimax = a.relative;
  if (a.rank == "max-abs")
    options.rank_by = Loss::MaxAbs;
  else if (a.rank == "max-rel")
    options.rank_by = Loss::MaxRel;
  else if (a.rank != "rmse")
    throw Error("unknown ranking '" + a.rank + "' (rmse, max-abs, max-rel)", {"--rank"});

  nlohmann::json j;
  j["schema"] = "shaderfit.rational/1";
  j["target"] = problem.target.name();
  j["variable"] = var;
  j["domain"] = {problem.domain.lo, problem.domain.hi};
  j["fit"] = a.minimax ? "minimax" : a.fit;
  for (const Condition& c : problem.conditions) j["conditions"].push_back(c.text);
  const bool to_stdout = a.json_path == "-";
  std::vector<double> values =
      sweep >= 0 ? params[static_cast<std::size_t>(sweep)].values : std::vector<double>{0.0};
  std::vector<RationalForm> forms;
  for (double v : values) {
    if (sweep >= 0) problem.parameter_values[static_cast<std::size_t>(sweep)] = v;
    RationalSummary summary;
    solve(options, problem, &summary);
    for (std::size_t i = 0; i < problem.forms.size(); ++i)
      for (const FormResult& r : summary.results)
        if (r.form == problem.forms[i] && r.status == FormStatus::PoleInDomain)
          throw Error(
              "form " + r.form.name(var) + ": " + r.message,
              {"--form", static_cast<int>(i / std::max<std::size_t>(transforms.size(), 1)) + 1, 1});
    if (summary.results.empty() || !summary.results.front().usable()) {
      const FormResult& r = summary.results.front();
      if (!problem.forms.empty())
        throw Error(fmt::format("form {} is {}: {}", r.form.name(var), form_status_name(r.status),
                                r.message),
                    {"--form"});
    }
    nlohmann::json run;
    for (std::size_t i = 0; i < names.size(); ++i)
      run["parameters"][names[i]] = problem.parameter_values[i];
    for (const FormResult& r : summary.results) run["results"].push_back(result_json(r, var));
    run["pareto"] = summary.pareto;
    j["runs"].push_back(run);
    if (forms.empty())
      for (const FormResult& r : summary.results) forms.push_back(r.form);
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
      const auto laws = parametric_laws(options, problem, pname, {*lo, *hi}, forms);
      if (!to_stdout)
        ctx.out << "coefficients as functions of " << pname << " on [" << format_number(*lo) << ", "
                << format_number(*hi) << "]:\n";
      for (const ParametricLaw& l : laws) {
        nlohmann::json lj = {{"form", l.form.name(var)},
                             {"usable", l.usable},
                             {"all_rational", l.all_rational},
                             {"formula", l.formula},
                             {"note", l.note}};
        for (const CoefficientLaw& c : l.coefficients)
          lj["coefficients"].push_back({{"name", c.coefficient},
                                        {"found", c.found},
                                        {"law", c.law},
                                        {"max_deviation", c.max_deviation}});
        j["parametric"].push_back(lj);
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
    ctx.out << j.dump(2) << '\n';
  } else if (!a.json_path.empty()) {
    std::ofstream f(a.json_path);
    if (!f) throw Error("cannot write '" + a.json_path + "'", {"--json"});
    f << j.dump(2) << '\n';
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
