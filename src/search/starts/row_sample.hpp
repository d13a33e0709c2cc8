// At most n of a problem's rows, evenly spread and in order (internal): what the operator
// probes read (search/operator_probe.hpp, search/library_operators.hpp).
#pragma once

#include <algorithm>
#include <cstddef>

#include "shaderfit/search/search.hpp"

namespace shaderfit::search_detail {

inline SearchProblem evenly_spread_rows(const SearchProblem& p, std::size_t n) {
  const std::size_t rows = p.target.size();
  n = std::min(rows, n);
  SearchProblem s;
  s.input_names = p.input_names;
  s.inputs.assign(p.inputs.size(), {});
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = k * rows / n;
    for (std::size_t v = 0; v < p.inputs.size(); ++v) s.inputs[v].push_back(p.inputs[v][i]);
    s.target.push_back(p.target[i]);
    if (!p.weights.empty()) s.weights.push_back(p.weights[i]);
  }
  return s;
}

}  // namespace shaderfit::search_detail
