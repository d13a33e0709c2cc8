#include <string>

#include "shaderfit/problem/problem.hpp"
#include "shaderfit/search/search.hpp"

namespace shaderfit {

SearchProblem search_problem(const Problem& problem, Loss loss, const std::string& weights_column,
                             const SourceLocation& weights_where) {
  const Dataset& d = problem.data;
  SearchProblem s;
  s.input_names = problem.inputs;
  for (const std::string& n : problem.inputs) s.inputs.push_back(d.numeric(n).values);
  s.target = d.numeric(problem.target).values;
  const std::string& weights = weights_column.empty() ? problem.weights : weights_column;
  if (loss == Loss::Display) {
    if (!problem.scene)
      throw Error(
          "the display loss needs a scene: the pixels the function shades weigh the rows "
          "(docs/scenes.md)",
          {"SearchOptions::loss"});
    if (!weights.empty())
      throw Error("the display loss weighs the rows by the scene's pixels: give no weights",
                  weights_where);
    s.weights = problem.display_weights;
  } else if (!weights.empty()) {
    if (d.find(weights) == nullptr) {
      std::string names;
      for (const auto& n : d.names()) names += (names.empty() ? "" : ", ") + n;
      throw Error("no column '" + weights + "' in " + (d.source.empty() ? "the data" : d.source) +
                      " (columns: " + names + ")",
                  weights_where);
    }
    s.weights = d.numeric(weights).values;
  }
  s.reference = problem.reference;
  s.validate();
  return s;
}

}  // namespace shaderfit
