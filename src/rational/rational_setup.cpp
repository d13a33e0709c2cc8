#include "shaderfit/rational/rational_setup.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>

#include "shaderfit/core/error.hpp"
#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/reference/domain.hpp"
#include "shaderfit/reference/language.hpp"

namespace shaderfit::rational {

namespace {

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

constexpr const char* kParameters = "RationalSetup::parameters";
constexpr const char* kDomain = "RationalSetup::domain";

// NAME=V1,V2,...
Param parse_param(const std::string& text, int index) {
  const SourceLocation where{kParameters, index, 0};
  const auto eq = text.find('=');
  Param p;
  p.name = text.substr(0, eq);
  while (!p.name.empty() && p.name.back() == ' ') p.name.pop_back();
  if (eq == std::string::npos || p.name.empty())
    throw Error("expected NAME=VALUE[,VALUE...] in '" + text + "'", {kParameters, index, 1});
  int offset = static_cast<int>(eq) + 1;
  for (const std::string& v : split_commas(text.substr(eq + 1))) {
    p.values.push_back(constant(v, where, offset));
    offset += static_cast<int>(v.size()) + 1;
  }
  return p;
}

// "LO,HI" or "x=LO:HI" (reference/domain.hpp, without a count), for the variable `variable`.
Interval parse_domain(std::string text, const std::string& variable) {
  if (text.find('=') != std::string::npos) {
    const reference::DomainAxis axis = reference::parse_domain_axis(text, kDomain);
    if (axis.name != variable)
      throw Error("the domain is of '" + axis.name + "', but the variable is '" + variable + "'",
                  {kDomain, 1, 1});
    if (axis.count > 0)
      throw Error("a sample count has no use here: give " + variable + "=LO:HI", {kDomain, 1, 1});
    return {axis.lo, axis.hi};
  }
  std::erase_if(text, [](char c) { return c == '[' || c == ']'; });
  const auto parts = split_commas(text);
  if (parts.size() != 2)
    throw Error("expected LO,HI or " + variable + "=LO:HI in '" + text + "'", {kDomain, 1, 1});
  const Interval d{constant(parts[0], {kDomain, 1, 0}, 0),
                   constant(parts[1], {kDomain, 1, 0}, static_cast<int>(parts[0].size()) + 1)};
  if (!(d.lo < d.hi))
    throw Error("the domain's lower end must be below its upper end", {kDomain, 1, 1});
  return d;
}

// The target: a built-in by name, a formula, or a shader function.
Target make_target(const RationalSetup& a, const std::vector<std::string>& names) {
  constexpr const char* kTarget = "RationalSetup::target";
  if (!a.reference_source.empty() || !a.function.empty()) {
    if (!a.target.empty())
      throw Error("give either RationalSetup::target or a shader function, not both", {kTarget});
    if (a.function.empty())
      throw Error("name the function of the shader source to approximate",
                  {"RationalSetup::function"});
    if (a.reference_source.empty())
      throw Error(
          "RationalSetup::function names a function of a shader source, which is not "
          "given",
          {"RationalSetup::function"});
    return Target::shader(a.reference_source,
                          a.reference_path.empty() ? "shader" : a.reference_path, a.function,
                          a.variable, names, "RationalSetup::variable");
  }
  if (a.target.empty())
    throw Error(
        "RationalSetup::target is required (a built-in name, a formula or a shader function)",
        {kTarget});
  // A bare name that is neither the variable nor a parameter means a built-in: report it as an
  // unknown target.
  const bool bare = a.target != a.variable &&
                    std::find(names.begin(), names.end(), a.target) == names.end() &&
                    std::all_of(a.target.begin(), a.target.end(), [](char c) {
                      return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
                    });
  if (!bare || Target::is_builtin(a.target))
    return bare ? Target::builtin(a.target, kTarget)
                : Target::formula(a.target, a.variable, names, kTarget);
  const std::vector<std::string> functions = reference::reference_function_names();
  if (std::find(functions.begin(), functions.end(), a.target) != functions.end())
    throw Error("unknown target '" + a.target + "': as a formula, write " + a.target + "(" +
                    a.variable + ")",
                {kTarget});
  return Target::builtin(a.target, kTarget);  // throws, listing the built-ins
}

}  // namespace

PreparedRational prepare_rational(const RationalSetup& a) {
  // Parameters: at most one may take several values (a sweep).
  std::vector<Param> params;
  for (std::size_t i = 0; i < a.parameters.size(); ++i)
    params.push_back(parse_param(a.parameters[i], static_cast<int>(i) + 1));
  PreparedRational out;
  RationalProblem& problem = out.problem;
  std::vector<std::string> names;
  for (std::size_t i = 0; i < params.size(); ++i) {
    if (std::find(names.begin(), names.end(), params[i].name) != names.end())
      throw Error("parameter " + params[i].name + " given twice",
                  {kParameters, static_cast<int>(i) + 1, 1});
    names.push_back(params[i].name);
    if (params[i].values.size() > 1) {
      if (out.sweep >= 0)
        throw Error("only one parameter may take several values",
                    {kParameters, static_cast<int>(i) + 1, 1});
      out.sweep = static_cast<int>(i);
    }
  }
  problem.target = make_target(a, names);
  problem.parameter_names = names;
  for (const Param& p : params) problem.parameter_values.push_back(p.values.front());
  problem.domain = a.domain.empty() ? problem.target.natural_domain()
                                    : parse_domain(a.domain, problem.target.variable());
  for (std::size_t i = 0; i < a.conditions.size(); ++i)
    problem.conditions.push_back(parse_condition(
        a.conditions[i], names, {"RationalSetup::conditions", static_cast<int>(i) + 1, 0}));
  const std::string& var = problem.target.variable();
  if (a.count > 0 && !a.forms.empty())
    throw Error("use RationalSetup::count or RationalSetup::forms, not both",
                {"RationalSetup::count"});
  // Explicit forms, in each transform (or in the variable itself).
  std::vector<Transform> transforms;
  for (const std::string& t : a.transforms)
    transforms.push_back(Transform::parse(t, var, "RationalSetup::transforms"));
  for (const std::string& text : a.forms) {
    RationalForm f = parse_form(text, "RationalSetup::forms");
    for (const Transform& t :
         transforms.empty() ? std::vector<Transform>{Transform::identity()} : transforms) {
      f.variable = t;
      problem.forms.push_back(f);
    }
  }
  out.transform_count = std::max<std::size_t>(transforms.size(), 1);
  RationalOptions& options = out.options;
  options.coefficient_count = a.count;
  options.transforms = transforms;
  options.fit = a.fit;
  options.relative_minimax = a.relative_minimax;
  options.rank_by = a.rank_by;
  out.sweep_values = out.sweep >= 0 ? params[static_cast<std::size_t>(out.sweep)].values
                                    : std::vector<double>{0.0};
  return out;
}

std::string_view fit_name(Fit fit) {
  switch (fit) {
    case Fit::None: return "none";
    case Fit::LeastSquares: return "lsq";
    case Fit::Minimax: return "minimax";
  }
  return "none";
}

RationalReport solve_prepared(PreparedRational& prepared) {
  RationalProblem& problem = prepared.problem;
  const std::string& var = problem.target.variable();
  RationalReport report;
  report.target = problem.target.name();
  report.variable = var;
  report.domain = problem.domain;
  report.fit = prepared.options.fit;
  for (const Condition& c : problem.conditions) report.conditions.push_back(c.text);
  report.parameter_names = problem.parameter_names;
  std::vector<RationalForm> forms;
  // Progress over the whole sweep: every value solves the same number of forms.
  RationalOptions options = prepared.options;
  options.on_progress = nullptr;
  const RationalOptions quiet = options;
  std::size_t run = 0;
  if (prepared.options.on_progress)
    options.on_progress = [&](const Progress& p) {
      prepared.options.on_progress(
          {run * p.total + p.done, prepared.sweep_values.size() * p.total, p.unit});
    };
  for (double v : prepared.sweep_values) {
    if (prepared.sweep >= 0) problem.parameter_values[static_cast<std::size_t>(prepared.sweep)] = v;
    RationalSummary summary;
    solve(options, problem, &summary);
    ++run;
    for (std::size_t i = 0; i < problem.forms.size(); ++i)
      for (const FormResult& r : summary.results)
        if (r.form == problem.forms[i] && r.status == FormStatus::PoleInDomain)
          throw Error(
              "form " + r.form.name(var) + ": " + r.message,
              {"RationalSetup::forms", static_cast<int>(i / prepared.transform_count) + 1, 1});
    if (!problem.forms.empty() && !summary.results.empty() && !summary.results.front().usable()) {
      const FormResult& r = summary.results.front();
      throw Error(
          fmt::format("form {} is {}: {}", r.form.name(var), form_status_name(r.status), r.message),
          {"RationalSetup::forms"});
    }
    if (forms.empty())
      for (const FormResult& r : summary.results) forms.push_back(r.form);
    report.runs.push_back({problem.parameter_values, std::move(summary)});
  }
  if (prepared.sweep >= 0) {
    const auto [lo, hi] =
        std::minmax_element(prepared.sweep_values.begin(), prepared.sweep_values.end());
    if (*lo < *hi) {
      report.swept_parameter = problem.parameter_names[static_cast<std::size_t>(prepared.sweep)];
      report.sweep_range = {*lo, *hi};
      report.laws =
          parametric_laws(quiet, problem, report.swept_parameter, report.sweep_range, forms);
    }
  }
  return report;
}

}  // namespace shaderfit::rational
