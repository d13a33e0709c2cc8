// The front's door: a formula that is NaN or infinite on any row never enters, whatever the
// caller's metrics say, and a member's numbers are those of the formula it shows.
#include "search/search_context.hpp"

#include <gtest/gtest.h>

#include <cmath>

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

}  // namespace
}  // namespace shaderfit::search_detail
