// Three problems from the literature, each recovered exactly by the search (docs/search.md has
// their ground truth, sampling and the times measured). Times are printed, never asserted.
#include <gtest/gtest.h>

#include <cstdio>
#include <functional>

#include "search/run/seed_problem_test_util.hpp"
#include "shaderfit/core/random.hpp"
#include "shaderfit/search/search.hpp"

namespace shaderfit {
namespace {

struct Literature {
  const char* name;
  std::vector<std::string> inputs;
  std::vector<std::pair<double, double>> ranges;  // uniform sampling range of each input
  std::size_t rows;
  std::function<double(const std::vector<double>&)> truth;
};

SearchProblem sample(const Literature& l, std::uint64_t seed) {
  Rng rng(seed);
  SearchProblem p;
  p.input_names = l.inputs;
  p.inputs.assign(l.inputs.size(), {});
  std::vector<double> row(l.inputs.size());
  for (std::size_t i = 0; i < l.rows; ++i) {
    for (std::size_t v = 0; v < row.size(); ++v) {
      row[v] = uniform(rng, l.ranges[v].first, l.ranges[v].second);
      p.inputs[v].push_back(row[v]);
    }
    p.target.push_back(l.truth(row));
  }
  return p;
}

void expect_recovered(const Literature& l) {
  const SearchProblem p = sample(l, 2024);
  double sum_y2 = 0;
  for (double y : p.target) sum_y2 += y * y;
  const double exact = 1e-24 * sum_y2 / static_cast<double>(p.target.size());  // float64 round-off
  SearchOptions o = test::seed_task_options();
  o.evolve = false;
  o.time_limit_s = 300;  // a bound, not an expectation
  o.max_enumeration_cost = 6;
  o.stop_at = SearchTarget{exact, 1e9};
  SearchSummary s;
  run_search(o, p, &s);
  ASSERT_FALSE(s.front.empty());
  const FrontMember& best = s.front.back();
  EXPECT_LE(best.metrics.mse, exact) << l.name << ": " << best.formula;
  std::printf("%s: %s (cost %g, mse %.3g) found after %.1f ms\n", l.name, best.formula.c_str(),
              best.cost, best.metrics.mse, best.time_s * 1e3);
}

TEST(Literature, Nguyen3) {
  // Uy et al. 2011, Nguyen-3: x^5 + x^4 + x^3 + x^2 + x, 20 points with x ~ U[-1, 1].
  expect_recovered({"Nguyen-3", {"x"}, {{-1, 1}}, 20, [](const std::vector<double>& v) {
                      const double x = v[0];
                      return x * x * x * x * x + x * x * x * x + x * x * x + x * x + x;
                    }});
}

TEST(Literature, SchlickSmithMasking) {
  // Schlick's approximation of Smith masking (Karis 2013): G1(v) = v / (v (1 - k) + k).
  expect_recovered(
      {"Schlick-Smith G1",
       {"v", "k"},
       {{0.01, 1}, {0.01, 1}},
       1000,
       [](const std::vector<double>& a) { return a[0] / (a[0] * (1 - a[1]) + a[1]); }});
}

TEST(Literature, FeynmanThinLens) {
  // AI Feynman I.27.6 (Udrescu & Tegmark 2020): f = 1 / (1/d1 + n/d2), inputs in U[1, 5].
  expect_recovered({"Feynman I.27.6",
                    {"d1", "d2", "n"},
                    {{1, 5}, {1, 5}, {1, 5}},
                    1000,
                    [](const std::vector<double>& a) { return 1 / (1 / a[0] + a[2] / a[1]); }});
}

}  // namespace
}  // namespace shaderfit
