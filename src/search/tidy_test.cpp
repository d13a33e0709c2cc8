// The tidy step: noise constants removed or snapped on exact data, fitted constants kept on
// inexact data, the front recomputed, and (acceptance of issue 17) exact physics formulas found
// by a search printed with no constant fitted to rounding noise.
#include "search/tidy.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>

#include "search/search_context.hpp"
#include "search/seed_problem_test_util.hpp"
#include "shaderfit/core/random.hpp"
#include "shaderfit/cost/cost_model.hpp"
#include "shaderfit/expr/parse.hpp"

namespace shaderfit::search_detail {
namespace {

constexpr double kPi = std::numbers::pi;

// Inputs uniform in [lo, hi], the target computed exactly by `f` (float64).
SearchProblem exact_problem(std::vector<std::string> names, double lo, double hi,
                            const std::function<double(const std::vector<double>&)>& f) {
  Rng rng(11);
  SearchProblem p;
  p.input_names = std::move(names);
  p.inputs.assign(p.input_names.size(), {});
  std::vector<double> row(p.input_names.size());
  for (int i = 0; i < 500; ++i) {
    for (std::size_t k = 0; k < row.size(); ++k) {
      row[k] = uniform(rng, lo, hi);
      p.inputs[k].push_back(row[k]);
    }
    p.target.push_back(f(row));
  }
  return p;
}

// The member for `formula`, its number literals as fitted parameters, scored as the search does.
FrontMember member(const SearchOptions& o, const SearchProblem& p, const char* formula) {
  ParseOptions po;
  po.variables = p.input_names;
  po.literals_as_parameters = true;
  FrontMember m;
  m.expression = parse_formula(formula, po);
  SearchContext ctx(o, p);
  m.metrics = ctx.score(m.expression);
  m.loss = loss_value(o.loss, m.metrics);
  m.cost = expression_cost(m.expression, o.cost);
  m.nodes = m.expression.size();
  m.formula = formula;
  return m;
}

std::vector<FrontMember> tidied(const SearchProblem& p, std::vector<FrontMember> front) {
  std::uint64_t evaluations = 0;
  return tidy_front(test::seed_task_options(), p, std::move(front), &evaluations);
}

std::string tidied_formula(const SearchProblem& p, const char* formula) {
  const std::vector<FrontMember> t = tidied(p, {member(test::seed_task_options(), p, formula)});
  return t.size() == 1 ? t[0].formula : "(front of " + std::to_string(t.size()) + ")";
}

TEST(Tidy, SimpleValues) {
  EXPECT_EQ(nearest_simple_value(1.0000000000000027), 1.0);
  EXPECT_EQ(nearest_simple_value(-1.6512056166817444e-11), 0.0);
  EXPECT_EQ(nearest_simple_value(6.283185307906383), 2 * kPi);
  EXPECT_EQ(nearest_simple_value(0.0795774715), 1 / (4 * kPi));
  EXPECT_EQ(nearest_simple_value(0.34), 1.0 / 3);
  EXPECT_EQ(nearest_simple_value(0.3), 1 / kPi);
  EXPECT_EQ(nearest_simple_value(-2.74), -2.75);
  EXPECT_EQ(nearest_simple_value(0.69), std::numbers::ln2);
  EXPECT_EQ(nearest_simple_value(1e6), 32.0);
  const std::span<const double> s = simple_values();
  EXPECT_TRUE(std::is_sorted(s.begin(), s.end()));
}

TEST(Tidy, RemovesAndSnapsNoiseConstantsOnExactData) {
  const SearchProblem mu =
      exact_problem({"mu", "Nn"}, 0.5, 4.0, [](const auto& v) { return v[0] * v[1]; });
  EXPECT_EQ(tidied_formula(mu, "mu * Nn - -1.6512056166817444e-11"), "mu * Nn");
  const SearchProblem d = exact_problem({"d"}, 0.5, 4.0, [](const auto& v) { return v[0]; });
  EXPECT_EQ(tidied_formula(d, "d / 1.0000000000000027"), "d");
  const SearchProblem qv = exact_problem(
      {"q", "v", "r"}, 0.5, 4.0, [](const auto& v) { return v[0] * v[1] / (2 * kPi * v[2]); });
  EXPECT_EQ(tidied_formula(qv, "(q * v - -1.07e-10) / (6.283185307906383 * r - 7.9e-10)"),
            "q * v / (6.283185307179586 * r)");
  // A large constant added and subtracted: the offset moves inside and cancels.
  const SearchProblem wh = exact_problem({"omega", "h"}, 0.5, 4.0,
                                         [](const auto& v) { return v[0] * v[1] / (2 * kPi); });
  EXPECT_EQ(tidied_formula(wh, "0.15915494309152647 * (omega * h - 65536) + 10430.378350446284"),
            "0.15915494309189535 * (omega * h)");
}

TEST(Tidy, KeepsConstantsTheDataNeeds) {
  // Fitted to inexact data: snapping any constant would cost more than 1e-9 of the loss.
  const SearchProblem p = exact_problem({"x"}, 0.0, 1.0, [](const auto& v) {
    return 0.3 * v[0] + 1e-3 + 0.01 * std::sin(40 * v[0]);
  });
  SearchOptions o = test::seed_task_options();
  const FrontMember m = member(o, p, "0.3000001 * x + 0.0010002");
  const std::vector<FrontMember> t = tidied(p, {m});
  ASSERT_EQ(t.size(), 1u);
  EXPECT_EQ(t[0].formula, m.formula);
  EXPECT_EQ(t[0].expression, m.expression);
  EXPECT_EQ(t[0].loss, m.loss);
}

TEST(Tidy, RecomputesTheFront) {
  // The exact d and the noisy d / 1.0000000000000027: tidied, the second is the first again.
  const SearchProblem d = exact_problem({"d"}, 0.5, 4.0, [](const auto& v) { return v[0]; });
  SearchOptions o = test::seed_task_options();
  const std::vector<FrontMember> t =
      tidied(d, {member(o, d, "d"), member(o, d, "d / 1.0000000000000027")});
  ASSERT_EQ(t.size(), 1u);
  EXPECT_EQ(t[0].formula, "d");
  EXPECT_EQ(t[0].cost, 0);
}

TEST(Tidy, KeepsUnsnappedFittedConstantsAsParameters) {
  const SearchProblem p =
      exact_problem({"x"}, 0.5, 4.0, [](const auto& v) { return 0.123456789 * v[0]; });
  SearchOptions o = test::seed_task_options();
  const std::vector<FrontMember> t = tidied(p, {member(o, p, "0.123456789 * x + 1e-13")});
  ASSERT_EQ(t.size(), 1u);
  EXPECT_EQ(t[0].formula, "0.123456789 * x");
  ASSERT_EQ(t[0].expression.parameters.size(), 1u);
  EXPECT_EQ(t[0].expression.parameter_values[0], 0.123456789);
}

// A constant of the formula (a literal or a fitted parameter) that rounding noise would leave:
// tiny, or within 1e-7 of a simple value without being it.
bool noise_constant(double c) {
  const double s = nearest_simple_value(c);
  return c != s && std::abs(c - s) <= 1e-7 * std::max(1.0, std::abs(s));
}

// Issue 17's acceptance: exact physics formulas, searched (with a start formula whose constants
// the search refits, to rounding noise); the members that fit exactly print with no constant
// fitted to noise.
TEST(Tidy, ExactPhysicsFormulasPrintWithoutNoiseConstants) {
  struct Case {
    const char* name;
    std::vector<std::string> inputs;
    std::function<double(const std::vector<double>&)> f;
    std::vector<std::string> start;  // formulas the search refits (SearchOptions::start)
  };
  const std::vector<Case> cases = {
      {"q / (4 pi epsilon r^2)",
       {"q", "epsilon", "r"},
       [](const auto& v) { return v[0] / (4 * kPi * v[1] * v[2] * v[2]); },
       {"0.08 * q / (epsilon * r^2) + 0.01"}},
      {"m g z",
       {"m", "g", "z"},
       [](const auto& v) { return v[0] * v[1] * v[2]; },
       {"1.1 * m * g * z - 0.1"}},
  };
  for (const Case& c : cases) {
    const SearchProblem p = exact_problem(c.inputs, 0.5, 2.0, c.f);
    SearchOptions o = test::seed_task_options();
    o.threads = 1;
    o.seed = 3;
    o.time_limit_s = 600;  // the candidate budget stops it
    o.max_candidates = 1000000;
    o.max_enumeration_cost = 3;
    o.start = c.start;
    SearchSummary s;
    run_search(o, p, &s);
    double scale = 0;
    for (double y : p.target) scale += y * y / static_cast<double>(p.target.size());
    int exact = 0;
    for (const FrontMember& m : s.front) {
      std::printf("%s: cost %g loss %.3g  %s\n", c.name, m.cost, m.loss, m.formula.c_str());
      if (!(m.metrics.mse <= 1e-24 * scale)) continue;
      ++exact;
      for (const Node& n : m.expression.nodes) {
        if (n.op == Op::Const) {
          EXPECT_FALSE(noise_constant(n.value)) << m.formula;
        }
      }
      for (double v : m.expression.parameter_values) EXPECT_FALSE(noise_constant(v)) << m.formula;
      EXPECT_EQ(m.formula.find("e-"), std::string::npos) << m.formula;
    }
    EXPECT_GE(exact, 1) << c.name;
  }
}

}  // namespace
}  // namespace shaderfit::search_detail
