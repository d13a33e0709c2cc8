#include "search/uniform_terminals.hpp"

#include <algorithm>
#include <cmath>

#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/expr/parse.hpp"

namespace shaderfit::search_detail {

namespace {

// The enumeration's leaf records hold an input's index in a signed byte.
constexpr std::size_t kMaxLeaves = 100;
std::size_t inputs_and_terminals(const SearchProblem& p, const std::vector<Expression>& t) {
  return p.inputs.size() + t.size();
}

// The shapes, `u` standing for the input.
constexpr const char* kShapes[] = {"1/u", "u^2", "1/u^2", "sqrt(u)", "log2(u)", "exp2(u)"};

}  // namespace

std::vector<Expression> uniform_terminals(const SearchProblem& problem,
                                          const SearchOptions& options) {
  std::vector<Expression> out;
  std::vector<std::vector<double>> columns;
  const std::size_t rows = problem.target.size();
  for (const std::string& u : options.uniform) {
    const auto at = std::find(problem.input_names.begin(), problem.input_names.end(), u);
    if (at == problem.input_names.end()) continue;
    const std::size_t v = static_cast<std::size_t>(at - problem.input_names.begin());
    for (const char* shape : kShapes) {
      Expression e = parse_formula(shape, {.variables = {"u"}});
      for (Node& n : e.nodes)
        if (n.op == Op::Var) n.index = static_cast<std::int16_t>(v);
      e.variables = problem.input_names;
      std::vector<double> column(rows);
      const double* inputs[] = {problem.inputs[v].data()};
      Expression one = e;
      one.variables = {u};
      for (Node& n : one.nodes)
        if (n.op == Op::Var) n.index = 0;
      evaluate(one, inputs, column, {.threads = 1});
      const bool finite =
          std::all_of(column.begin(), column.end(), [](double x) { return std::isfinite(x); });
      const bool varies =
          std::any_of(column.begin(), column.end(), [&](double x) { return x != column.front(); });
      const bool new_values = std::find(columns.begin(), columns.end(), column) == columns.end() &&
                              column != problem.inputs[v];
      if (!finite || !varies || !new_values) continue;
      // The enumeration numbers its leaves in a byte, inputs first.
      if (inputs_and_terminals(problem, out) >= kMaxLeaves) return out;
      columns.push_back(std::move(column));
      out.push_back(std::move(e));
    }
  }
  return out;
}

}  // namespace shaderfit::search_detail
