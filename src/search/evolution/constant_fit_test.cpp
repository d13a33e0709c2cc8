// Minimax constants in the search: front members fitted for max_abs, and the final polish.
#include "search/evolution/constant_fit.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "search/run/seed_problem_test_util.hpp"
#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/fit/fit.hpp"

namespace shaderfit::search_detail {
namespace {

using test::fresnel_seed_problem;

ErrorMetrics metrics_of(const Expression& e, const SearchProblem& p) {
  std::vector<const double*> cols;
  for (const auto& c : p.inputs) cols.push_back(c.data());
  std::vector<double> f(p.target.size());
  evaluate(e, cols, f, {.threads = 1});
  return error_metrics(f, p.target);
}

SearchOptions max_loss_search(Loss loss) {
  SearchOptions o = test::seed_task_options();
  o.loss = loss;
  o.threads = 1;
  o.time_limit_s = 600;  // counts stop it, never the clock
  o.max_enumeration_cost = 3;
  o.max_enumeration_share = 1.0;
  o.max_candidates = 20000;
  o.population = 32;
  o.seed = 3;
  return o;
}

// Acceptance: with loss max_abs, every front member with fitted constants errs by no more than
// the same formula with its constants refitted by least squares. For max_rel the same in the
// relative error (least squares weighted by 1/y^2, the rel loss's fit).
TEST(SearchMinimax, FrontMembersBeatTheirLeastSquaresRefit) {
  const SearchProblem p = fresnel_seed_problem();
  std::vector<double> inverse_square;
  for (double y : p.target) inverse_square.push_back(1 / (y * y));
  for (Loss loss : {Loss::MaxAbs, Loss::MaxRel}) {
    SearchSummary s;
    run_search(max_loss_search(loss), p, &s);
    const bool rel = loss == Loss::MaxRel;
    std::vector<const double*> cols;
    for (const auto& c : p.inputs) cols.push_back(c.data());
    int fitted = 0;
    for (const FrontMember& m : s.front) {
      EXPECT_EQ(m.loss, rel ? m.metrics.max_rel : m.metrics.max_abs);
      if (m.expression.parameters.empty()) continue;
      ++fitted;
      Expression lsq = m.expression;
      FitOptions fo;
      fo.max_iterations = 200;
      FitSummary fs;
      fit_parameters(fo, {&lsq, cols, p.target, rel ? inverse_square : std::vector<double>{}}, &fs);
      lsq.parameter_values = fs.parameters;
      const ErrorMetrics e = metrics_of(lsq, p);
      EXPECT_LE(m.loss, (rel ? e.max_rel : e.max_abs) * (1 + 1e-12)) << m.formula;
    }
    EXPECT_GT(fitted, 0) << loss_name(loss);
  }
}

// The polish frees a member's literals and fits them minimax: Schlick's 1 becomes 0.88 and the
// max error falls from 0.177 to 0.119 at the same cost (docs/search.md). Not for other losses.
TEST(SearchMinimax, PolishFreesLiteralsAndKeepsOnlyImprovements) {
  const SearchProblem p = fresnel_seed_problem();
  const Expression schlick = parse_formula("r0 + (1 - r0) * x^5", {.variables = {"r0", "x"}});
  for (Loss loss : {Loss::MaxAbs, Loss::Mse}) {
    SearchOptions o = test::seed_task_options();
    o.loss = loss;
    SearchContext ctx(o, p);
    ASSERT_TRUE(ctx.offer(schlick, loss_value(loss, ctx.score(schlick)), SearchPhase::Start));
    const double before = ctx.front.members()[0].metrics.max_abs;
    polish_front_minimax(ctx, 60);
    ASSERT_EQ(ctx.front.size(), 1u);
    const FrontMember m = ctx.front.members()[0];
    if (loss == Loss::Mse) {
      EXPECT_EQ(m.formula, "r0 + (1 - r0) * x^5");
      EXPECT_TRUE(m.expression.parameters.empty());
      continue;
    }
    EXPECT_NEAR(before, 0.177, 0.001);
    EXPECT_NEAR(m.metrics.max_abs, 0.119, 0.001) << m.formula;
    EXPECT_EQ(m.origin, SearchPhase::Start);
    ASSERT_EQ(m.expression.parameters.size(), 1u);
    EXPECT_NEAR(m.expression.parameter_values[0], 0.88, 0.005);
    // Polishing the optimum again changes nothing.
    const std::string formula = m.formula;
    polish_front_minimax(ctx, 60);
    EXPECT_EQ(ctx.front.members()[0].formula, formula);
    // No time: nothing is polished.
    SearchContext none(o, p);
    ASSERT_TRUE(none.offer(schlick, before, SearchPhase::Start));
    polish_front_minimax(none, 0);
    EXPECT_TRUE(none.front.members()[0].expression.parameters.empty());
  }
}

}  // namespace
}  // namespace shaderfit::search_detail
