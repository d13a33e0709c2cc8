// The front's door: a formula that is NaN or infinite on any row never enters, whatever the
// caller's metrics say, and a member's numbers are those of the formula it shows; the stratified
// samples of rows the strategies score on.
#include "search/search_context.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <set>

#include "search/run/seed_problem_test_util.hpp"
#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/expr/parse.hpp"

namespace shaderfit::search_detail {
namespace {

// x = 0, 0.05, ..., 1 (0.5 exactly among them); y = x^2; the row x = 0.5 weighs 0.
SearchProblem grid_problem() {
  SearchProblem p;
  p.input_names = {"x"};
  p.inputs.resize(1);
  for (int i = 0; i <= 20; ++i) {
    const double x = i / 20.0;
    p.inputs[0].push_back(x);
    p.target.push_back(x * x);
    p.weights.push_back(i == 10 ? 0.0 : 1.0);
  }
  return p;
}

Expression formula(const char* text) { return parse_formula(text, {.variables = {"x"}}); }

// The metrics error_metrics gives, which skip rows of weight 0.
ErrorMetrics weighted_metrics(const Expression& e, const SearchProblem& p) {
  std::vector<double> f(p.target.size());
  const double* col = p.inputs[0].data();
  evaluate(e, std::span<const double* const>(&col, 1), f, {.threads = 1});
  return error_metrics(f, p.target, {}, p.weights);
}

TEST(SearchContext, NonFiniteOnAnyRowNeverEntersTheFront) {
  const SearchProblem p = grid_problem();
  for (Loss loss : {Loss::Mse, Loss::MaxAbs}) {
    SearchOptions o = test::seed_task_options();
    o.loss = loss;
    SearchContext ctx(o, p);
    // Infinite only on the weight-0 row: its weighted metrics are finite, yet it is refused.
    const Expression pole = formula("1 / (x - 0.5)");
    ASSERT_TRUE(std::isfinite(weighted_metrics(pole, p).mse));
    EXPECT_FALSE(
        ctx.offer(pole, loss_value(loss, weighted_metrics(pole, p)), SearchPhase::Evolution));
    // NaN on the rows x < 0.3, even when offered with made-up finite metrics.
    EXPECT_FALSE(ctx.offer(formula("log2(x - 0.3)"), 0.0, SearchPhase::Evolution));
    EXPECT_FALSE(ctx.offer(formula("sqrt(x - 0.7) + x"), 0.0, SearchPhase::Evolution));
    // Finite results through non-finite intermediates: rcp(inf) = 0, max(NaN, 0) = 0.
    EXPECT_FALSE(ctx.offer(formula("rcp(1 / (x - 0.5)) + x"), 0.0, SearchPhase::Evolution));
    EXPECT_FALSE(ctx.offer(formula("max(log2(x - 0.3), 0) + x"), 0.0, SearchPhase::Evolution));
    EXPECT_FALSE(ctx.offer(formula("rcp((2 / 0)^3 - 0.5) + x"), 0.0, SearchPhase::Evolution));
    EXPECT_EQ(ctx.front.size(), 0u);
    // Finite everywhere: enters.
    const Expression fine = formula("x * 0.5");
    EXPECT_TRUE(
        ctx.offer(fine, loss_value(loss, weighted_metrics(fine, p)), SearchPhase::Evolution));
    EXPECT_EQ(ctx.front.size(), 1u);
  }
}

TEST(SearchContext, MembersCarryTheMetricsOfTheirOwnFormula) {
  const SearchProblem p = grid_problem();
  SearchOptions o = test::seed_task_options();
  SearchContext ctx(o, p);
  const Expression e = formula("x * 0.5");
  const double flattering = 0;  // better than the truth
  ASSERT_TRUE(ctx.offer(e, flattering, SearchPhase::Evolution));
  const FrontMember m = ctx.front.members().at(0);
  EXPECT_EQ(m.metrics.mse, weighted_metrics(e, p).mse);
  EXPECT_GT(m.loss, 0.0);
}

TEST(SearchContext, SearchFrontsHoldOnlyFormulasFiniteOnEveryRow) {
  // y = 1 / (x - 0.5) on every row but x = 0.5, where the target is 0 and the weight 0: the
  // exact formula is infinite there, so it must not be on the front.
  SearchProblem p = grid_problem();
  for (std::size_t i = 0; i < p.target.size(); ++i)
    p.target[i] = p.weights[i] == 0 ? 0.0 : 1.0 / (p.inputs[0][i] - 0.5);
  SearchOptions o = test::seed_task_options();
  o.threads = 1;
  o.evolve = false;
  o.max_enumeration_cost = 3;
  o.time_limit_s = 60;
  SearchSummary s;
  run_search(o, p, &s);
  ASSERT_FALSE(s.front.empty());
  const double* col = p.inputs[0].data();
  for (const FrontMember& m : s.front) {
    std::vector<double> f(p.target.size());
    evaluate(m.expression, std::span<const double* const>(&col, 1), f, {.threads = 1});
    for (double v : f) EXPECT_TRUE(std::isfinite(v)) << m.formula;
    EXPECT_TRUE(std::isfinite(m.loss)) << m.formula;
  }
}

TEST(SearchContext, StratifiedRowsDrawOneRowFromEachStratumOfTheTarget) {
  // 100 rows whose targets fall from 99 to 0: ten strata of ten rows by target.
  std::vector<double> y(100);
  for (std::size_t i = 0; i < y.size(); ++i) y[i] = 99.0 - static_cast<double>(i);
  std::vector<std::size_t> rows(y.size());
  std::iota(rows.begin(), rows.end(), 0);
  Rng rng(1);
  const std::vector<std::size_t> picked = stratified_rows(y, rows, 10, rng);
  ASSERT_EQ(picked.size(), 10u);
  EXPECT_TRUE(std::is_sorted(picked.begin(), picked.end()));
  std::set<int> strata;
  for (std::size_t r : picked) strata.insert(static_cast<int>(y[r]) / 10);
  EXPECT_EQ(strata.size(), 10u);
  Rng again(1);
  EXPECT_EQ(stratified_rows(y, rows, 10, again), picked);  // the generator decides
  // No more rows than wanted: all of them, sorted, and nothing drawn.
  Rng few(1), untouched(1);
  EXPECT_EQ(stratified_rows(y, {7, 3, 5}, 10, few), (std::vector<std::size_t>{3, 5, 7}));
  EXPECT_EQ(few(), untouched());
}

}  // namespace
}  // namespace shaderfit::search_detail
