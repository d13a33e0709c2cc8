#include "shaderfit/eval/dataset_eval.hpp"

#include "shaderfit/core/error.hpp"
#include "shaderfit/data/dataset.hpp"
#include "shaderfit/eval/evaluate_in.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/expr/print.hpp"

namespace shaderfit {

Expression parse_formula_on(std::string_view text, const Dataset& data, const std::string& source) {
  ParseOptions opts;
  opts.variables = data.names();
  opts.source = source;
  Expression e = parse_formula(text, opts);
  e.drop_unused_variables();
  for (const std::string& v : e.variables) (void)data.numeric(v);
  return e;
}

namespace {

// A grouping column's values as group labels (numbers as format_number writes them).
std::vector<std::string> group_labels(const Dataset& data, const std::string& group) {
  const Column& col = data.column(group);
  std::vector<std::string> labels(data.rows());
  for (std::size_t i = 0; i < data.rows(); ++i)
    labels[i] = col.numeric() ? format_number(col.values[i]) : col.labels[i];
  return labels;
}

}  // namespace

void check_uniform_in_groups(const Dataset& data, std::span<const std::string> uniform,
                             std::span<const std::string> groups) {
  const SourceLocation where{"UniformInputs"};
  for (const std::string& u : uniform) {
    if (data.find(u) == nullptr || !data.find(u)->numeric())
      throw Error("uniform input '" + u + "' is not a numeric column of the data", where);
    const std::vector<double>& v = data.column(u).values;
    for (const std::string& g : groups) {
      for (const auto& [label, rows] : group_rows(group_labels(data, g))) {
        for (std::size_t r : rows) {
          if (v[r] == v[rows.front()]) continue;
          throw Error("uniform input '" + u + "' varies within group " + g + "=" + label + " (" +
                          format_number(v[rows.front()]) + " in row " +
                          std::to_string(rows.front() + 1) + ", " + format_number(v[r]) +
                          " in row " + std::to_string(r + 1) + ")",
                      where);
        }
      }
    }
  }
}

namespace {

std::vector<const double*> bind(const Expression& e, const Dataset& data) {
  std::vector<const double*> cols;
  cols.reserve(e.variables.size());
  for (const std::string& v : e.variables) cols.push_back(data.numeric(v).values.data());
  return cols;
}

}  // namespace

std::vector<double> evaluate_on(const Expression& e, const Dataset& data,
                                const EvalOptions& options) {
  const std::vector<const double*> cols = bind(e, data);
  std::vector<double> out(data.rows());
  evaluate(e, std::span<const double* const>(cols), std::span<double>(out), options);
  return out;
}

std::vector<double> evaluate_on(const Expression& e, const Dataset& data, Precision precision) {
  const std::vector<const double*> cols = bind(e, data);
  std::vector<double> out(data.rows());
  evaluate_in(precision, e, cols, out);
  return out;
}

EvalFormulaResult evaluate_formula_on(std::string_view text, const std::string& source,
                                      const Dataset& data, std::span<const double> target,
                                      std::span<const std::string> groups, Precision precision) {
  EvalFormulaResult r;
  r.input = std::string(text);
  r.expression = parse_formula_on(text, data, source);
  const Expression& e = r.expression;
  r.formula = to_infix(e);
  const std::vector<double> p = evaluate_on(e, data, precision);
  r.all = error_metrics(p, target);
  for (const std::string& g : groups) {
    for (const auto& [label, rows] : group_rows(group_labels(data, g)))
      r.groups.push_back({g, label, error_metrics(p, target, rows)});
  }
  return r;
}

}  // namespace shaderfit
