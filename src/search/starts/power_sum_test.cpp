// Exact power sums (search/power_sum.hpp): found where the data is one, nowhere else.
#include "search/starts/power_sum.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>

#include "search/run/drawn_problem_test_util.hpp"
#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/expr/parse.hpp"

namespace shaderfit::search_detail {
namespace {

using V = std::vector<double>;

SearchProblem drawn(std::vector<std::pair<double, double>> ranges,
                    const std::function<double(const V&)>& f, int rows = 2000) {
  std::vector<std::string> names;
  for (std::size_t k = 0; k < ranges.size(); ++k) names.push_back("in" + std::to_string(k));
  return test::drawn_problem(std::move(names), ranges, f, 11, rows);
}

// The largest relative difference between the formula found and the target, over every row.
double worst_relative(const std::string& text, const SearchProblem& p) {
  ParseOptions po;
  for (std::size_t k = 0; k < p.inputs.size(); ++k) po.variables.push_back("x" + std::to_string(k));
  const Expression e = parse_formula(text, po);
  double worst = 0;
  for (std::size_t r = 0; r < p.target.size(); ++r) {
    V row;
    for (const V& c : p.inputs) row.push_back(c[r]);
    worst = std::max(worst, std::abs(evaluate_scalar(e, row) / p.target[r] - 1));
  }
  return worst;
}

TEST(PowerSum, FoundWhereTheTargetIsOne) {
  const std::vector<
      std::pair<std::vector<std::pair<double, double>>, std::function<double(const V&)>>>
      cases = {
          // rho / sqrt(1 - v^2 / c^2): M = rho, p = -2.
          {{{1, 5}, {1, 2}, {3, 10}},
           [](const V& x) { return x[0] / std::sqrt(1 - x[1] * x[1] / (x[2] * x[2])); }},
          // mom sqrt(Bx^2 + By^2 + Bz^2): three terms under a square root.
          {{{1, 5}, {1, 5}, {1, 5}, {1, 5}},
           [](const V& x) { return x[0] * std::sqrt(x[1] * x[1] + x[2] * x[2] + x[3] * x[3]); }},
          // Schlick's G1 with k = alpha / 2, times an input: 1 / y is linear in 1, alpha and
          // alpha / n over M = l.
          {{{0.05, 1}, {0.01, 1}, {0.1, 1}},
           [](const V& x) { return x[2] * x[0] / (x[0] * (1 - x[1] / 2) + x[1] / 2); }},
          // w^4 / (w^2 - w0^2)^2 times a product, w0 > w: p = -1/2 over M = a b^2 w^4 w0^-4,
          // whose exponents for w and w0 the fit tilts (4.7, -4.8).
          {{{1, 3}, {1, 3}, {1, 2}, {3, 5}},
           [](const V& x) {
             const double d = x[2] * x[2] - x[3] * x[3];
             return x[0] * x[1] * x[1] * std::pow(x[2], 4) / (d * d);
           }},
          // A Gaussian over its width: log2 |y| is linear in log2 sigma and (theta / sigma)^2.
          {{{1, 3}, {1, 3}},
           [](const V& x) {
             return std::exp(-x[1] * x[1] / (2 * x[0] * x[0])) / (2.5066282746310002 * x[0]);
           }},
          // A power product alone: the transform is constant, a sum of no terms.
          {{{0.5, 4}, {1, 3}, {2, 6}, {0.1, 1}},
           [](const V& x) { return 0.3 * x[2] / (x[0] * x[1] * x[1] * x[3]); }},
          // A Boltzmann factor: one power product of five inputs in the logarithm.
          {{{1, 2}, {0.5, 1.5}, {1, 2}, {1, 3}, {2, 4}, {0.5, 1}},
           [](const V& x) { return x[0] * std::exp(-x[1] * x[2] * x[5] / (x[3] * x[4])); }},
          // A Gaussian with a mean: four terms in the logarithm.
          {{{0.5, 2}, {-1, 1}, {-0.5, 0.5}},
           [](const V& x) {
             const double u = (x[1] - x[2]) / x[0];
             return std::exp(-u * u / 2) / (2.5066282746310002 * x[0]);
           }},
          // M = x0 / (x1 x2) from the inputs whose log-fit exponents are integers, and a sum of
          // a product of four others beside one input.
          {{{1, 3}, {0.5, 2}, {1, 4}, {1, 2}, {0.5, 3}, {1, 5}, {2, 3}, {1, 2}},
           [](const V& x) {
             return x[0] / (x[1] * x[2]) *
                    (x[3] + x[4] * x[7] / (x[5] * x[6] * x[6]));
           }},
          // A velocity sum: a sum over a sum, fitted as y = N - y E at once.
          {{{0.1, 0.9}, {-0.5, 0.8}, {1, 1.5}},
           [](const V& x) { return (x[0] + x[1]) / (1 + x[0] * x[1] / (x[2] * x[2])); }},
          // Planck's law in frequency, a logistic and tanh: C M0 / h(exp2(a m)).
          {{{1, 3}, {2, 4}, {0.5, 2}},
           [](const V& x) {
             return 0.7 * x[1] * x[1] * x[1] / x[2] / (std::exp(0.4 * x[1] / (x[0] * x[2])) - 1);
           }},
          {{{0, 2}, {1, 3}}, [](const V& x) { return x[1] / (1 + std::exp(-x[0])); }},
          {{{0.2, 3}, {1, 2}, {1, 4}},
           [](const V& x) { return x[1] * x[2] * std::tanh(x[0] * x[2] / x[1]); }},
          // A negative target, with an input that takes both signs.
          {{{-2, 2}, {1, 3}, {1, 2}},
           [](const V& x) { return -std::sqrt(x[0] * x[0] + 2 * x[1] * x[2]); }},
      };
  for (std::size_t k = 0; k < cases.size(); ++k) {
    SCOPED_TRACE("case " + std::to_string(k));
    const SearchProblem p = drawn(cases[k].first, cases[k].second);
    const auto found = exact_power_sum(p);
    ASSERT_TRUE(found.has_value());
    EXPECT_LT(worst_relative(*found, p), 1e-10) << *found;
  }
}

TEST(PowerSum, NothingWhereItIsNot) {
  // Functions that are no such sum.
  EXPECT_FALSE(exact_power_sum(drawn({{0, 2}, {1, 3}}, [](const V& x) {
                 return x[1] / (1 + std::exp(-x[0]) + 0.5 * x[0]);
               })).has_value());
  EXPECT_FALSE(exact_power_sum(drawn({{1, 5}, {1, 5}, {1, 5}}, [](const V& x) {
                 return x[0] * x[1] * std::sin(x[2]);
               })).has_value());
  // One of them with noise of 1e-5 relative: not exact.
  const std::vector<std::pair<double, double>> box = {{1, 5}, {1, 2}, {3, 10}};
  Rng rng(3);
  EXPECT_FALSE(exact_power_sum(test::drawn_problem(
                                   {"rho", "v", "c"}, box,
                                   [&](const V& x) {
                                     const double y =
                                         x[0] / std::sqrt(1 - x[1] * x[1] / (x[2] * x[2]));
                                     return y * (1 + 1e-5 * uniform(rng, -1, 1));
                                   },
                                   11, 2000))
                   .has_value());
  // An input that is 0 on a row, too few rows, and one input (the enumeration's).
  EXPECT_FALSE(exact_power_sum(drawn({{0, 0}, {1, 2}, {1, 2}}, [](const V& x) {
                 return x[1] * x[2];
               })).has_value());
  EXPECT_FALSE(exact_power_sum(drawn(
                                   {{1, 2}, {1, 2}, {1, 2}},
                                   [](const V& x) { return 1 / (x[0] + x[1] * x[2]); }, 40))
                   .has_value());
  EXPECT_FALSE(
      exact_power_sum(drawn({{1, 2}}, [](const V& x) { return 1 / (x[0] + 1); })).has_value());
}

TEST(PowerSum, SteepFunctions) {
  // The log fit's exponent for x0 is about 30 here: no quotient is made of it (it would not
  // print as x0^k), and the logarithm's form is found and parses.
  const SearchProblem p = drawn({{1, 2}, {1, 2}, {1, 2}}, [](const V& x) {
    return std::exp(20 * x[0]) * x[1] * x[1] * x[2];
  });
  const auto found = exact_power_sum(p);
  ASSERT_TRUE(found.has_value());
  EXPECT_LT(worst_relative(*found, p), 1e-10) << *found;
}

TEST(PowerSum, TenInputsStayCheap) {
  // 4 inputs try the most fits of the rational sum, 10 the most columns.
  for (const std::size_t n : {4, 10}) {
    std::vector<std::pair<double, double>> box(n, {0.5, 2.0});
    const SearchProblem p = drawn(
        box, [n](const V& x) { return std::exp(x[0] - x[n - 1]) + x[1]; }, 100000);
    const auto t0 = std::chrono::steady_clock::now();
    EXPECT_FALSE(exact_power_sum(p).has_value());
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    std::printf("power sum: %.1f ms for %zu inputs (no sum)\n", ms, n);
  }
}

}  // namespace
}  // namespace shaderfit::search_detail
