// End-to-end tests of run_search: the seed task, reproducibility, the literature problems, and
// the validation of problems and options. No timed assertions: times are printed, not checked.
#include "shaderfit/search/search.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "search/run/seed_problem_test_util.hpp"
#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/search/front/front_table.hpp"

namespace shaderfit {
namespace {

using test::fresnel_seed_problem;

double mse_of(const char* formula, const SearchProblem& p) {
  ParseOptions po;
  po.variables = p.input_names;
  const Expression e = parse_formula(formula, po);
  std::vector<const double*> cols;
  for (const auto& c : p.inputs) cols.push_back(c.data());
  std::vector<double> f(p.target.size());
  evaluate(e, cols, f, {.threads = 1});
  return error_metrics(f, p.target).mse;
}

const FrontMember* best_within(const SearchSummary& s, double max_cost) {
  const FrontMember* best = nullptr;
  for (const FrontMember& m : s.front)
    if (m.cost <= max_cost && (best == nullptr || m.loss < best->loss)) best = &m;
  return best;
}

TEST(Search, EnumerationReachesTheSeedFormula) {
  const SearchProblem p = fresnel_seed_problem();
  const double target_mse = mse_of("r0 + (x - r0) * x^4", p);
  SearchOptions o = test::seed_task_options();
  o.evolve = false;
  o.time_limit_s = 120;  // never the stop: the level cap is
  o.max_enumeration_cost = 4;
  o.stop_at = SearchTarget{target_mse * (1 + 1e-9), 4};
  SearchSummary s;
  run_search(o, p, &s);
  const FrontMember* m = best_within(s, 4);
  ASSERT_NE(m, nullptr);
  EXPECT_LE(m->metrics.mse, target_mse * (1 + 1e-9)) << m->formula;
  EXPECT_EQ(s.termination, Termination::TargetReached);
  std::printf("seed target: %s (mse %.4g, cost %g) after %.1f ms\n", m->formula.c_str(),
              m->metrics.mse, m->cost, m->time_s * 1e3);
  // Schlick's formula (cost 5) is dominated: a member no worse in both error and cost.
  const double schlick = mse_of("r0 + (1 - r0) * x^5", p);
  EXPECT_LT(m->metrics.mse, schlick);
}

SearchOptions small_budget(int threads) {
  SearchOptions o = test::seed_task_options();
  o.threads = threads;
  o.time_limit_s = 600;        // counts stop it, never the clock
  o.max_enumeration_cost = 2;  // the enumeration ends by its level cap
  o.max_enumeration_share = 1.0;
  o.max_candidates = 8000;  // the evolution by the candidate budget
  o.population = 32;
  o.seed = 7;
  return o;
}

// Inputs of both signs, with a target computed by `f`.
SearchProblem signed_problem(double (*f)(double, double)) {
  Rng rng(5);
  SearchProblem p;
  p.input_names = {"a", "b"};
  p.inputs.assign(2, {});
  for (int i = 0; i < 400; ++i) {
    const double a = uniform(rng, -1.0, 1.0), b = uniform(rng, -1.0, 1.0);
    p.inputs[0].push_back(a);
    p.inputs[1].push_back(b);
    p.target.push_back(f(a, b));
  }
  return p;
}

TEST(Search, EnumerationUsesSignAndCopysignWhenAsked) {
  SearchOptions o = test::seed_task_options();
  o.evolve = false;
  o.time_limit_s = 120;
  o.max_enumeration_cost = 4;
  o.operators = parse_operator_list("+,-,*,^,copysign,sign");
  o.stop_at = SearchTarget{1e-20, 4};
  for (auto f : {+[](double a, double b) { return std::copysign(a * a, b); },
                 +[](double a, double b) { return (a > 0 ? 1.0 : -1.0) * b; }}) {
    const SearchProblem p = signed_problem(f);
    SearchSummary s;
    run_search(o, p, &s);
    const FrontMember* m = best_within(s, 4);
    ASSERT_NE(m, nullptr);
    EXPECT_LE(m->metrics.mse, 1e-20) << m->formula;
    EXPECT_EQ(s.termination, Termination::TargetReached) << m->formula;
    std::printf("found %s (cost %g)\n", m->formula.c_str(), m->cost);
  }
}

TEST(Search, EvolutionUsesSelectWhenAsked) {
  SearchOptions o = small_budget(1);
  o.evolution_operators = parse_operator_list("select,sign");
  const SearchProblem p =
      signed_problem(+[](double a, double b) { return a >= 0 ? b * b : a + 0.5; });
  SearchSummary s;
  run_search(o, p, &s);
  ASSERT_FALSE(s.front.empty());
  bool any = false;
  for (const FrontMember& m : s.front) any = any || m.formula.find("select(") != std::string::npos;
  std::printf("front of %zu, select used: %d; best %s\n", s.front.size(), any ? 1 : 0,
              s.front.back().formula.c_str());
}

TEST(Search, RacingEvolutionFrontHoldsTheLossOnEveryRow) {
  // The seed task's 4,096 rows are more than the fit rows and the race rows together, so the
  // evolution races: a child is refitted and scored on a sample before any is scored on every row.
  // What enters the front still carries its formula's loss on every row.
  const SearchProblem p = fresnel_seed_problem();
  SearchOptions o = small_budget(1);
  o.enumerate = false;
  SearchSummary s;
  run_search(o, p, &s);
  EXPECT_GT(s.generations, 0u);
  std::vector<const double*> cols;
  for (const auto& c : p.inputs) cols.push_back(c.data());
  int evolved = 0;
  for (const FrontMember& m : s.front) {
    std::vector<double> f(p.target.size());
    evaluate(m.expression, cols, f, {.threads = 1});
    EXPECT_NEAR(m.loss, error_metrics(f, p.target).mse, 1e-12 * m.loss) << m.formula;
    evolved += m.origin == SearchPhase::Evolution ? 1 : 0;
  }
  EXPECT_GT(evolved, 0);
}

void expect_same_front(const SearchSummary& a, const SearchSummary& b) {
  ASSERT_EQ(a.front.size(), b.front.size());
  for (std::size_t i = 0; i < a.front.size(); ++i) {
    EXPECT_EQ(a.front[i].formula, b.front[i].formula);
    EXPECT_EQ(a.front[i].cost, b.front[i].cost);
    EXPECT_EQ(a.front[i].loss, b.front[i].loss);
  }
  EXPECT_EQ(a.candidates, b.candidates);
  EXPECT_EQ(a.generations, b.generations);
}

TEST(Search, SameSeedSameResultWithOneThread) {
  const SearchProblem p = fresnel_seed_problem();
  SearchSummary a, b;
  run_search(small_budget(1), p, &a);
  run_search(small_budget(1), p, &b);
  EXPECT_GT(a.generations, 0u);
  expect_same_front(a, b);
}

TEST(Search, SameSeedSameResultWithTwoThreads) {
  // Documented in docs/search.md: tiles merge in order and islands synchronise, so the thread
  // count does not change the result when no stop is by the clock.
  const SearchProblem p = fresnel_seed_problem();
  SearchSummary a, b;
  run_search(small_budget(1), p, &a);
  run_search(small_budget(2), p, &b);
  expect_same_front(a, b);
}

TEST(Search, NewMembersAreReportedAsFoundAndTheFrontIsSorted) {
  const SearchProblem p = fresnel_seed_problem();
  SearchOptions o = test::seed_task_options();
  o.evolve = false;
  o.max_enumeration_cost = 2;
  int calls = 0;
  o.on_new_member = [&](const FrontMember& m) {
    ++calls;
    EXPECT_FALSE(m.formula.empty());
    // The best constant first (a polynomial of degree 0, as written and fitted); the rest is
    // enumerated.
    if (m.origin == SearchPhase::Polynomial)
      EXPECT_EQ(m.cost, 0) << m.formula;
    else
      EXPECT_EQ(m.origin, SearchPhase::Enumeration);
  };
  SearchSummary s;
  run_search(o, p, &s);
  EXPECT_GE(calls, static_cast<int>(s.front.size()));
  for (std::size_t i = 1; i < s.front.size(); ++i) {
    EXPECT_LT(s.front[i - 1].cost, s.front[i].cost);
    EXPECT_GT(s.front[i - 1].loss, s.front[i].loss);
  }
  // Every formula reads back and scores what the front says.
  ParseOptions po;
  po.variables = p.input_names;
  for (const FrontMember& m : s.front) EXPECT_NO_THROW(parse_formula(m.formula, po)) << m.formula;
}

TEST(Search, InterruptReturnsTheFrontSoFar) {
  const SearchProblem p = fresnel_seed_problem();
  std::atomic<bool> stop{false};
  SearchOptions o = test::seed_task_options();
  o.interrupt = &stop;
  o.on_new_member = [&](const FrontMember& m) {
    if (m.cost >= 3) stop.store(true);
  };
  SearchSummary s;
  run_search(o, p, &s);
  EXPECT_TRUE(s.interrupted);
  EXPECT_EQ(s.termination, Termination::Interrupted);
  EXPECT_FALSE(s.front.empty());
}

TEST(Search, EveryLossRuns) {
  const SearchProblem p = fresnel_seed_problem();
  for (Loss k : {Loss::Mse, Loss::Rmse, Loss::MaxAbs, Loss::Relative, Loss::Log}) {
    SearchOptions o = test::seed_task_options();
    o.loss = k;
    o.evolve = false;
    o.max_enumeration_cost = 2;
    SearchSummary s;
    run_search(o, p, &s);
    ASSERT_FALSE(s.front.empty()) << loss_name(k);
    EXPECT_EQ(s.front.back().loss, loss_value(k, s.front.back().metrics));
  }
}

TEST(Search, WeightsAndNodeCost) {
  SearchProblem p = fresnel_seed_problem();
  p.weights.assign(p.target.size(), 1.0);
  for (std::size_t i = 0; i < p.weights.size(); i += 2) p.weights[i] = 3.0;
  SearchOptions o = test::seed_task_options();
  o.cost = CostTarget::Nodes;
  o.evolve = false;
  o.max_enumeration_cost = 5;
  SearchSummary s;
  run_search(o, p, &s);
  ASSERT_FALSE(s.front.empty());
  for (const FrontMember& m : s.front) EXPECT_EQ(m.cost, static_cast<double>(m.nodes));
}

}  // namespace
}  // namespace shaderfit
