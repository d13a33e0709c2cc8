// The user's start formulas (SearchOptions::start): parsing and its errors, the refit for the
// run's loss, and what the front holds afterwards.
#include "search/starts/start.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "search/run/seed_problem_test_util.hpp"
#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/expr/parse.hpp"

namespace shaderfit::search_detail {
namespace {

// y = exp(x) on [-1, 1], 201 points: a quadratic is close, not exact.
SearchProblem quadratic_problem() {
  SearchProblem p;
  p.input_names = {"x"};
  p.inputs.resize(1);
  for (int i = 0; i <= 200; ++i) {
    const double x = -1 + i / 100.0;
    p.inputs[0].push_back(x);
    p.target.push_back(std::exp(x));
  }
  return p;
}

ErrorMetrics metrics(const Expression& e, const SearchProblem& p) {
  std::vector<double> f(p.target.size());
  const std::vector<const double*> columns = {p.inputs[0].data()};
  evaluate(e, columns, f, {.threads = 1});
  return error_metrics(f, p.target);
}

TEST(StartFormulas, ParseOverTheInputsWithLiteralsFree) {
  SearchOptions o = test::seed_task_options();
  o.start = {"1 + 1*x + 0.5*x^2", "pi * x"};
  const auto s = parse_start_formulas(o, quadratic_problem());
  ASSERT_EQ(s.size(), 2U);
  EXPECT_TRUE(s[0].written.parameters.empty());
  EXPECT_EQ(s[0].free.parameter_values, (std::vector<double>{1.0, 1.0, 0.5}));
  EXPECT_TRUE(s[1].free.parameters.empty());  // pi is exact
  EXPECT_EQ(s[0].written.variables, (std::vector<std::string>{"x"}));
}

TEST(StartFormulas, ErrorsAreLocatedAtTheFieldAndTheFormula) {
  SearchOptions o = test::seed_task_options();
  o.start = {"x + 1", "x * (r0 + 1)"};
  try {
    parse_start_formulas(o, quadratic_problem());
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.where().source, "SearchOptions::start");
    EXPECT_EQ(e.where().line, 2);
    EXPECT_EQ(e.where().column, 6);
    EXPECT_NE(e.message().find("unknown variable 'r0'"), std::string::npos) << e.what();
  }
  o.start = {"x +"};
  SearchSummary summary;
  EXPECT_THROW(run_search(o, quadratic_problem(), &summary), Error);
}

TEST(StartFormulas, RefitMinimisesTheRunsLoss) {
  const SearchProblem p = quadratic_problem();
  SearchOptions o = test::seed_task_options();
  o.start = {"1 + 1*x + 0.5*x^2"};
  const Expression free = parse_start_formulas(o, p)[0].free;
  o.loss = Loss::Mse;
  const ErrorMetrics lsq = metrics(refit_for_loss(free, o, p), p);
  o.loss = Loss::MaxAbs;
  const ErrorMetrics minimax = metrics(refit_for_loss(free, o, p), p);
  // Each best in its own loss; the minimax quadratic of exp on [-1, 1] errs by 0.04502.
  EXPECT_LT(lsq.mse, minimax.mse);
  EXPECT_LT(minimax.max_abs, lsq.max_abs);
  EXPECT_NEAR(minimax.max_abs, 0.04502, 0.0005);
  EXPECT_LT(metrics(free, p).max_abs, 1) << "the written values are the start";
}

TEST(StartFormulas, TheFrontHoldsTheRefitWithNoOtherStrategy) {
  const SearchProblem p = quadratic_problem();
  SearchOptions o = test::seed_task_options();
  o.start = {"1 + 1*x + 0.5*x^2"};
  o.loss = Loss::MaxAbs;
  o.enumerate = false;
  o.evolve = false;
  o.threads = 1;
  SearchSummary s;
  run_search(o, p, &s);
  // The best constant, and the refit, which dominates the written form (same cost).
  ASSERT_EQ(s.front.size(), 2U);
  EXPECT_EQ(s.front[0].cost, 0);
  EXPECT_EQ(s.front[1].origin, SearchPhase::Start);
  EXPECT_NEAR(s.front[1].metrics.max_abs, 0.04502, 0.0005);
  EXPECT_EQ(s.candidates, 4U);
}

// The front starts at the best constant for the loss, which no literal or input comes near:
// y = 7 + x^2 on [0, 1], the mean 7 1/3 for mse, the midrange 7.5 for max_abs.
TEST(StartFormulas, TheFrontStartsAtTheBestConstant) {
  const SearchProblem p = test::unit_interval_problem(1000, [](double x) { return 7 + x * x; });
  for (const auto& [loss, best] : {std::pair{Loss::Mse, 7.0 + 1.0 / 3.0}, {Loss::MaxAbs, 7.5}}) {
    SearchOptions o = test::seed_task_options();
    o.loss = loss;
    o.evolve = false;
    o.threads = 1;
    o.max_candidates = 20'000;
    SearchSummary s;
    run_search(o, p, &s);
    ASSERT_FALSE(s.front.empty());
    const FrontMember& cheapest = s.front.front();
    EXPECT_EQ(cheapest.cost, 0) << cheapest.formula;
    ASSERT_TRUE(cheapest.expression.variables.empty() ||
                cheapest.formula.find('x') == std::string::npos)
        << cheapest.formula;
    EXPECT_NEAR(std::stod(cheapest.formula), best, 1e-3) << loss_name(loss);
  }
}

}  // namespace
}  // namespace shaderfit::search_detail
