// The seed task of the search benchmarks (docs/search.md, docs/gpu.md): fresnel-seed data,
// inputs r0 and x, target R; the target is a front member with MSE <= that of
// r0 + (x - r0) * x^4 and cost <= 4, timed on the search's own clock.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "search/run/seed_problem_test_util.hpp"
#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/search/search.hpp"

namespace shaderfit::bench {

inline SearchProblem seed_problem(std::uint64_t data_seed) {
  return test::fresnel_seed_problem(data_seed);
}

// MSE of the seed formula on p, with a hair of slack for float summation order.
inline double seed_target_mse(const SearchProblem& p) {
  ParseOptions po;
  po.variables = p.input_names;
  const Expression e = parse_formula("r0 + (x - r0) * x^4", po);
  const std::vector<const double*> cols = {p.inputs[0].data(), p.inputs[1].data()};
  std::vector<double> f(p.target.size());
  evaluate(e, cols, f, {.threads = 1});
  return error_metrics(f, p.target).mse * (1 + 1e-9);
}

// Runs the search until the target; returns the search-clock time at which the first front
// member meeting it was found, or -1 when none did.
inline double time_to_target(SearchOptions o, const SearchProblem& p, SearchSummary* s) {
  const double target = seed_target_mse(p);
  o.stop_at = SearchTarget{target, 4};
  run_search(o, p, s);
  double found = -1;
  for (const FrontMember& m : s->front)
    if (m.cost <= 4 && m.metrics.mse <= target)
      found = found < 0 ? m.time_s : std::min(found, m.time_s);
  return found;
}

}  // namespace shaderfit::bench
