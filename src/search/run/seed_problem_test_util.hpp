// Seed 001's Fresnel task as a search problem, for the search's tests and benchmarks: inputs r0
// and x, target R of the fresnel-seed data drawn with `data_seed`; and a one-input problem.
#pragma once

#include <cstdint>
#include <optional>

#include "shaderfit/core/random.hpp"
#include "shaderfit/data/fresnel_seed.hpp"
#include "shaderfit/search/options.hpp"
#include "shaderfit/search/search.hpp"

namespace shaderfit::test {

inline SearchProblem fresnel_seed_problem(std::uint64_t data_seed = 1) {
  Rng rng(data_seed);
  const Dataset d = make_fresnel_seed_dataset(rng);
  SearchProblem p;
  p.input_names = {"r0", "x"};
  p.inputs = {d.numeric("r0").values, d.numeric("x").values};
  p.target = d.numeric("R").values;
  return p;
}

// y = f(x) at x = 0, 1/n, ..., 1: input x.
template <class F>
SearchProblem unit_interval_problem(int n, F f) {
  SearchProblem p;
  p.input_names = {"x"};
  p.inputs.resize(1);
  for (int i = 0; i <= n; ++i) {
    const double x = static_cast<double>(i) / n;
    p.inputs[0].push_back(x);
    p.target.push_back(f(x));
  }
  return p;
}

// The search's options for the seed task: the defaults with the data set's own operators (the
// library's default is "auto"), as `shaderfit search --dataset fresnel-seed` runs it.
inline SearchOptions seed_task_options() {
  SearchOptions o;
  const std::optional<BuiltinDatasetInfo> info = builtin_dataset_info("fresnel-seed");
  set_search_option(o, "operators", info->operators);
  set_search_option(o, "evolution_operators", info->evolution_operators);
  return o;
}

}  // namespace shaderfit::test
