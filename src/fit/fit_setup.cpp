#include "shaderfit/fit/fit_setup.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <optional>

#include "shaderfit/core/error.hpp"
#include "shaderfit/core/random.hpp"
#include "shaderfit/eval/dataset_eval.hpp"
#include "shaderfit/eval/metrics.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/expr/print.hpp"
#include "shaderfit/fit/builtin_reference.hpp"
#include "shaderfit/fit/fit_blocks.hpp"
#include "shaderfit/reference/domain.hpp"
#include "shaderfit/reference/language.hpp"

namespace shaderfit {

namespace {

[[noreturn]] void fail(const std::string& message, const std::string& field) {
  throw Error(message, SourceLocation{field});
}

struct Param {
  std::string name;
  double start = 0;
};

std::vector<Param> parse_params(const std::vector<std::string>& specs) {
  std::vector<Param> out;
  for (const std::string& s : specs) {
    Param p;
    const std::size_t eq = s.find('=');
    p.name = s.substr(0, eq);
    if (eq != std::string::npos) {
      ParseOptions po;
      po.variables = {"__none__"};
      po.source = "FitSetup::parameters";
      p.start = evaluate_scalar(parse_formula(s.substr(eq + 1), po), std::vector<double>{0.0});
    }
    if (p.name.empty())
      fail("expected NAME or NAME=START, got '" + s + "'", "FitSetup::parameters");
    out.push_back(p);
  }
  return out;
}

std::string builtin_names() {
  std::string s;
  for (const reference::BuiltinFunction* r : builtin_references())
    s += (s.empty() ? "" : ", ") + std::string(r->name);
  return s;
}

bool looks_like_builtin_name(const std::string& s) {
  return s.find('-') != std::string::npos && std::all_of(s.begin(), s.end(), [](char c) {
           return std::islower(static_cast<unsigned char>(c)) ||
                  std::isdigit(static_cast<unsigned char>(c)) || c == '-';
         });
}

bool is_identifier(const std::string& s) {
  if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
  return std::all_of(s.begin(), s.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
  });
}

// What computes the columns beyond the data's and the reference, compiled once for every block's
// data: the definitions with the reference formula (or with "0", a placeholder, when the
// reference is a column or a shader function), and the shader function.
struct Programs {
  std::optional<reference::Program> columns;
  std::optional<reference::Program> shader;
  std::string description;  // of the reference
};

// `known` and the definitions' names.
std::vector<std::string> column_names(const std::vector<std::string>& known, const Programs& p) {
  std::vector<std::string> out = known;
  if (p.columns)
    for (const std::string& n : p.columns->output_names)
      if (n != reference::kReferenceOutput && p.columns->find_input(n) < 0) out.push_back(n);
  return out;
}

Programs compile_programs(const FitSetup& a, const std::vector<std::string>& known) {
  Programs p;
  const bool formula = !a.reference.empty();
  if (formula || !a.definitions.empty()) {
    reference::ReferenceText t;
    t.formula = formula ? a.reference : "0";
    t.variables = known;
    t.definitions = a.definitions;
    t.formula_source = "FitSetup::reference";
    t.definitions_source = "FitSetup::definitions";
    try {
      p.columns = reference::compile_reference(t);
    } catch (const Error& e) {
      // "fv-exat" reads as a difference of unknown names; say what the built-ins are instead.
      if (!formula || e.where().source != t.formula_source || !looks_like_builtin_name(a.reference))
        throw;
      fail("unknown reference '" + a.reference + "' (built-in: " + builtin_names() + ")",
           "FitSetup::reference");
    }
    if (formula) p.description = p.columns->description;
  }
  if (!a.reference_source.empty()) {
    reference::ReferenceText t;
    t.shader_source = a.reference_source;
    t.shader_path = a.reference_path.empty() ? "shader" : a.reference_path;
    t.function = a.function;
    p.shader = reference::compile_reference(t);
    const std::vector<std::string> names = column_names(known, p);
    for (const std::string& in : p.shader->inputs)
      if (std::find(names.begin(), names.end(), in) == names.end())
        fail("the parameter '" + in + "' of " + p.shader->description +
                 " is not a column (columns: " + fmt::format("{}", fmt::join(names, ", ")) + ")",
             "FitSetup::function");
    p.description = p.shader->description;
  }
  if (!a.target.empty()) p.description = "column " + a.target;
  return p;
}

// Adds the definitions' columns to `d` and returns the reference at every row.
std::vector<double> add_columns(const FitSetup& a, const Programs& p, Dataset& d) {
  std::vector<double> formula;
  if (p.columns) formula = add_program_columns(d, *p.columns);
  if (!a.target.empty()) return d.numeric(a.target).values;
  if (p.shader) return add_program_columns(d, *p.shader);
  return formula;
}

std::vector<double> weight_values(const FitSetup& a, const Dataset& d) {
  if (a.weight.empty()) return {};
  if (const Column* c = d.find(a.weight)) return d.numeric(c->name).values;
  return evaluate_on(parse_formula_on(a.weight, d, "FitSetup::weight"), d);
}

std::string label_of(const Column& c, std::size_t row) {
  return c.numeric() ? format_number(c.values[row]) : c.labels[row];
}

}  // namespace

PreparedFit prepare_fit(FitSetup a) {
  PreparedFit s;
  if (a.formula.empty()) fail("no formula to fit", "FitSetup::formula");
  const int references =
      int(!a.target.empty()) + int(!a.reference.empty()) + int(!a.reference_source.empty());
  if (references != 1)
    fail(references == 0 ? "no reference: give FitSetup::target COLUMN, FitSetup::reference "
                           "FORMULA or a shader function (FitSetup::reference_source)"
                         : "give one of FitSetup::target, FitSetup::reference and a shader "
                           "function (FitSetup::reference_source)",
         "FitSetup::target");
  if (a.reference_source.empty() != a.function.empty())
    fail(a.function.empty() ? "name the function of the shader source to fit"
                            : "FitSetup::function names a function of a shader source, which "
                              "is not given",
         "FitSetup::function");
  const bool generated = !a.domain.empty();
  const bool has_data = a.data.has_value();
  if (generated && has_data)
    fail("give either FitSetup::domain (sampled data) or FitSetup::data, not both",
         "FitSetup::domain");
  if (!generated && !has_data)
    fail("no data: give FitSetup::data or FitSetup::domain", "FitSetup::data");
  if (a.samples > 0 && !generated)
    fail("a design size is for a sampled domain (FitSetup::domain)", "FitSetup::samples");
  if (a.samples > 0 && a.random_samples > 0)
    fail("give either FitSetup::samples or FitSetup::random_samples, not both",
         "FitSetup::samples");
  if (!a.per_cell.empty() && a.grid.empty())
    fail("FitSetup::per_cell needs a grid: give FitSetup::grid name=lo:hi:cells",
         "FitSetup::per_cell");
  if (!a.per_group.empty() && !a.grid.empty())
    fail("use either FitSetup::per_group or a grid, not both", "FitSetup::per_group");

  std::vector<GridAxis> grid;
  for (const std::string& g : a.grid) grid.push_back(parse_grid_axis(g, "FitSetup::grid"));
  // The names the reference language may use: the grid's and domain's variables, or the data's
  // numeric columns named as identifiers ("reference" names the reference itself).
  std::vector<std::string> known;
  std::unique_ptr<Dataset> data;
  std::vector<GridCell> cells;
  Programs programs;
  std::vector<double> data_reference;  // with data: the reference at every row
  if (generated) {
    std::vector<reference::DomainAxis> domain;
    for (const GridAxis& g : grid) known.push_back(g.name);
    for (std::size_t k = 0; k < a.domain.size(); ++k) {
      const SourceLocation where{"FitSetup::domain", static_cast<int>(k + 1), 0};
      try {
        domain.push_back(reference::parse_domain_axis(a.domain[k], where.source));
      } catch (const Error& e) {
        throw Error(e.message(), where);
      }
      if (std::find(known.begin(), known.end(), domain.back().name) != known.end())
        throw Error("'" + domain.back().name + "' is named twice among the grid and the domain",
                    where);
      known.push_back(domain.back().name);
    }
    if (a.samples > 0 && domain.front().count > 0)
      fail("a design size is not used with counts on the domain's axes", "FitSetup::samples");
    programs = compile_programs(a, known);
    Rng rng(a.rng_seed);
    cells = sample_grid(grid, domain, a.samples, a.random_samples, rng, {"FitSetup::domain"});
    known = column_names(known, programs);
  } else {
    data = std::make_unique<Dataset>(std::move(*a.data));
    for (const Column& c : data->columns)
      if (c.numeric() && is_identifier(c.name) && c.name != reference::kReferenceOutput)
        known.push_back(c.name);
    programs = compile_programs(a, known);
    data_reference = add_columns(a, programs, *data);
    known = data->names();
  }
  s.reference_description = programs.description;
  for (const std::string& name : a.inputs)
    if (std::find(known.begin(), known.end(), name) == known.end())
      fail("input '" + name + "' is no column" + (generated ? " or sampled variable" : ""),
           "FitSetup::inputs");

  // The formula and its parameters.
  const std::vector<Param> params = parse_params(a.parameters);
  ParseOptions po;
  po.variables = known;
  po.source = "FitSetup::formula";
  for (const Param& p : params) {
    po.parameters.push_back(p.name);
    po.parameter_values.push_back(p.start);
  }
  Expression f = parse_formula(a.formula, po);
  if (f.parameters.empty())
    fail("the formula '" + to_infix(f) +
             "' has no free parameters to fit (name them with FitSetup::parameters NAME[=START])",
         "FitSetup::formula");
  for (std::size_t j = 0; j < f.parameters.size(); ++j) {
    const bool used = std::any_of(f.nodes.begin(), f.nodes.end(), [&](const Node& n) {
      return n.op == Op::Param && n.index == static_cast<int>(j);
    });
    if (!used)
      fail("parameter '" + f.parameters[j] + "' does not appear in the formula",
           "FitSetup::parameters");
  }
  f.drop_unused_variables();
  if (!a.inputs.empty())
    for (const std::string& v : f.variables)
      if (std::find(a.inputs.begin(), a.inputs.end(), v) == a.inputs.end()) {
        std::string list;
        for (const std::string& name : a.inputs) list += (list.empty() ? "" : ", ") + name;
        fail("the formula reads '" + v + "', which is not among the inputs (" + list + ")",
             "FitSetup::inputs");
      }
  s.problem.formula = f;
  // The rows where the reference is NaN or infinite: an error naming the first, or left out.
  const char* reference_field = !a.target.empty()      ? "FitSetup::target"
                                : !a.reference.empty() ? "FitSetup::reference"
                                                       : "FitSetup::function";
  const auto finite_rows = [&](const std::vector<double>& target, std::vector<std::size_t> rows,
                               const std::string& where) {
    if (rows.empty()) {
      rows.resize(target.size());
      for (std::size_t i = 0; i < rows.size(); ++i) rows[i] = i;
    }
    const auto bad = [&](std::size_t i) { return !std::isfinite(target[i]); };
    const auto first = std::find_if(rows.begin(), rows.end(), bad);
    if (first == rows.end()) return rows;
    if (!a.drop_nonfinite)
      fail(fmt::format("the reference is NaN or infinite at {} {} ({} such; leave them out: "
                       "FitSetup::drop_nonfinite)",
                       where, *first + 1, std::count_if(rows.begin(), rows.end(), bad)),
           reference_field);
    const auto kept = std::remove_if(rows.begin(), rows.end(), bad);
    s.dropped_nonfinite += static_cast<std::size_t>(rows.end() - kept);
    rows.erase(kept, rows.end());
    return rows;
  };

  // Scopes.
  s.problem.scopes.assign(f.parameters.size(), ParameterScope::global);
  auto per_block = [&](const std::string& name, const char* field) {
    const auto it = std::find(f.parameters.begin(), f.parameters.end(), name);
    if (it == f.parameters.end())
      fail("'" + name + "' is not a parameter (declare it with FitSetup::parameters)", field);
    s.problem.scopes[static_cast<std::size_t>(it - f.parameters.begin())] =
        ParameterScope::per_block;
  };
  std::string group_column;
  for (const std::string& g : a.per_group) {
    const std::size_t colon = g.find(':');
    if (colon == std::string::npos)
      fail("expected PARAM:COLUMN, got '" + g + "'", "FitSetup::per_group");
    const std::string column = g.substr(colon + 1);
    if (!group_column.empty() && column != group_column)
      fail("every per-group parameter must use the same column ('" + group_column + "' and '" +
               column + "')",
           "FitSetup::per_group");
    group_column = column;
    per_block(g.substr(0, colon), "FitSetup::per_group");
  }
  for (const std::string& c : a.per_cell) per_block(c, "FitSetup::per_cell");

  for (std::size_t k = 0; k < a.constraints.size(); ++k)
    s.problem.constraints.push_back(
        parse_constraint(a.constraints[k], f, "FitSetup::constraints " + std::to_string(k + 1)));
  if (!a.transform.empty()) {
    ParseOptions tp;
    tp.variables = f.variables;
    tp.variables.push_back("y");
    tp.source = "FitSetup::transform";
    Expression t = parse_formula(a.transform, tp);
    t.drop_unused_variables();
    s.problem.transform = t;
  }

  // Blocks.
  if (generated) {
    s.data_description =
        fmt::format("{} sampled cell{} of {} rows", cells.size(), cells.size() == 1 ? "" : "s",
                    cells.empty() ? 0 : cells.front().data.rows());
    if (!grid.empty()) s.grouping = fmt::format("per cell of a {}-axis grid", grid.size());
    for (GridCell& c : cells) {
      auto d = std::make_unique<Dataset>(std::move(c.data));
      const std::vector<double> target = add_columns(a, programs, *d);
      BlockSource src{
          d.get(),
          finite_rows(target, {},
                      c.label() == "all" ? "sampled point" : "cell " + c.label() + ", point"),
          {}};
      for (std::size_t i : src.rows) src.target.push_back(target[i]);
      // make_block reads every row for an empty row list; a cell left empty stays empty.
      FitBlock b = src.rows.empty()
                       ? FitBlock{c.label(),
                                  std::vector<std::vector<double>>(f.variables.size()),
                                  {},
                                  {},
                                  {}}
                       : make_block(*d, f, target, weight_values(a, *d), src.rows, c.label());
      b.context = c.centre;
      s.problem.blocks.push_back(std::move(b));
      s.sources.push_back(std::move(src));
      s.datasets.push_back(std::move(d));
    }
  } else {
    const Dataset& d = *data;
    s.data_description = fmt::format("{}, {} rows", a.data_name, d.rows());
    const std::vector<double>& target = data_reference;
    const std::vector<double> weights = weight_values(a, d);
    std::vector<std::pair<std::string, std::vector<std::size_t>>> groups;
    std::vector<std::vector<std::pair<std::string, double>>> contexts;
    if (!group_column.empty()) {
      const Column& col = d.column(group_column);
      std::vector<std::string> labels(d.rows());
      for (std::size_t i = 0; i < d.rows(); ++i) labels[i] = label_of(col, i);
      for (auto& [label, rows] : group_rows(labels)) {
        groups.emplace_back(group_column + "=" + label, rows);
        contexts.emplace_back();
        if (col.numeric()) contexts.back().emplace_back(group_column, col.values[rows.front()]);
      }
      s.grouping = "per " + group_column;
    } else if (!grid.empty()) {
      Rng unused(0);
      const std::vector<GridCell> shape = sample_grid(grid, {}, 0, 0, unused);
      std::vector<std::vector<std::size_t>> rows(shape.size());
      std::vector<const std::vector<double>*> cols;
      for (const GridAxis& g : grid) cols.push_back(&d.numeric(g.name).values);
      for (std::size_t i = 0; i < d.rows(); ++i) {
        std::size_t cell = 0;
        bool inside = true;
        for (std::size_t k = 0; k < grid.size(); ++k) {
          const long c = grid[k].cell_of((*cols[k])[i]);
          inside = inside && c >= 0;
          cell = cell * grid[k].cells + static_cast<std::size_t>(std::max(c, 0L));
        }
        if (inside)
          rows[cell].push_back(i);
        else
          ++s.dropped_rows;
      }
      for (std::size_t c = 0; c < shape.size(); ++c) {
        groups.emplace_back(shape[c].label(), std::move(rows[c]));
        contexts.push_back(shape[c].centre);
      }
      s.grouping = fmt::format("per cell of a {}-axis grid", grid.size());
    } else {
      std::vector<std::size_t> all(d.rows());
      for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
      groups.emplace_back("all", std::move(all));
      contexts.emplace_back();
    }
    for (std::size_t g = 0; g < groups.size(); ++g) {
      if (!groups[g].second.empty())
        groups[g].second = finite_rows(target, std::move(groups[g].second), "data row");
      BlockSource src{data.get(), groups[g].second, {}};
      for (std::size_t i : src.rows) src.target.push_back(target[i]);
      // make_block reads every row for an empty row list; an empty cell stays empty.
      FitBlock b = groups[g].second.empty()
                       ? FitBlock{groups[g].first,
                                  std::vector<std::vector<double>>(f.variables.size()),
                                  {},
                                  {},
                                  {}}
                       : make_block(d, f, target, weights, groups[g].second, groups[g].first);
      b.context = contexts[g];
      s.problem.blocks.push_back(std::move(b));
      s.sources.push_back(std::move(src));
    }
    s.datasets.push_back(std::move(data));
  }

  s.options = a.options;
  s.baselines = std::move(a.baselines);
  return s;
}

const char* loss_description(Loss l) {
  return l == Loss::Mse   ? "least squares"
         : l == Loss::Log ? "log2 error (least squares)"
                          : "max error (minimax)";
}

std::vector<BlockComparison> compare_blocks(const PreparedFit& fit,
                                            const FixedFormSummary& summary) {
  std::vector<BlockComparison> out(fit.problem.blocks.size());
  std::map<const Dataset*, std::vector<std::vector<double>>> cache;  // baseline values per data set
  for (std::size_t b = 0; b < out.size(); ++b) {
    const FitBlock& blk = fit.problem.blocks[b];
    const BlockSource& src = fit.sources[b];
    Expression e = fit.problem.formula;
    e.parameter_values = summary.blocks[b].parameters;
    std::vector<const double*> cols;
    for (const auto& c : blk.columns) cols.push_back(c.data());
    std::vector<double> v(blk.target.size());
    if (!v.empty()) evaluate(e, std::span<const double* const>(cols), std::span<double>(v));
    out[b].mse = error_metrics(v, blk.target).mse;
    auto& values = cache[src.data];
    if (values.empty())
      for (std::size_t k = 0; k < fit.baselines.size(); ++k)
        values.push_back(
            evaluate_on(parse_formula_on(fit.baselines[k], *src.data,
                                         "FitSetup::baselines " + std::to_string(k + 1)),
                        *src.data));
    for (const std::vector<double>& all : values) {
      std::vector<double> picked;
      for (std::size_t i : src.rows) picked.push_back(all[i]);
      out[b].baseline_mse.push_back(error_metrics(picked, src.target).mse);
    }
  }
  return out;
}

}  // namespace shaderfit
