// Search problems drawn for tests: each input uniform in its own range (an explicit seed), the
// target computed by a function in float64 and, with `digits` > 0, rounded to that many
// significant digits (as a CSV written so would hold it).
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "shaderfit/core/random.hpp"
#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/search/search.hpp"

namespace shaderfit::test {

inline SearchProblem drawn_problem(std::vector<std::string> names,
                                   const std::vector<std::pair<double, double>>& ranges,
                                   const std::function<double(const std::vector<double>&)>& f,
                                   std::uint64_t seed, int rows, int digits = 0) {
  Rng rng(seed);
  SearchProblem p;
  p.input_names = std::move(names);
  p.inputs.assign(p.input_names.size(), {});
  std::vector<double> row(p.input_names.size());
  for (int i = 0; i < rows; ++i) {
    for (std::size_t k = 0; k < row.size(); ++k) {
      row[k] = uniform(rng, ranges[k].first, ranges[k].second);
      p.inputs[k].push_back(row[k]);
    }
    double y = f(row);
    if (digits > 0) {
      char text[64];
      std::snprintf(text, sizeof text, "%.*e", digits - 1, y);
      y = std::strtod(text, nullptr);
    }
    p.target.push_back(y);
  }
  return p;
}

// The RMS difference between e (over the problem's inputs) and the problem's target, over the
// target's standard deviation.
inline double relative_rms(const Expression& e, const SearchProblem& p) {
  double mean = 0, err = 0, var = 0;
  for (double t : p.target) mean += t / static_cast<double>(p.target.size());
  for (std::size_t r = 0; r < p.target.size(); ++r) {
    std::vector<double> row;
    for (const std::vector<double>& c : p.inputs) row.push_back(c[r]);
    const double d = evaluate_scalar(e, row) - p.target[r];
    err += d * d;
    var += (p.target[r] - mean) * (p.target[r] - mean);
  }
  return std::sqrt(err / var);
}

}  // namespace shaderfit::test
