// Issue 16, item 5: targets spanning many orders of magnitude under the relative and log losses
// (the enumeration's screen must not overflow float32 on them), and pow with a variable exponent
// enumerated between computed classes when the operator set asks for it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "search/run/seed_problem_test_util.hpp"
#include "shaderfit/search/search.hpp"

namespace shaderfit {
namespace {

// x in [0.05, 1] on a grid, and y = x^n for n in `exponents` (n an input when there are several).
SearchProblem powers(const std::vector<double>& exponents) {
  SearchProblem p;
  p.input_names = {"x"};
  p.inputs.assign(exponents.size() > 1 ? 2 : 1, {});
  if (exponents.size() > 1) p.input_names.push_back("n");
  for (int i = 0; i < 128; ++i) {
    const double x = 0.05 + 0.95 * i / 127.0;
    for (double n : exponents) {
      p.inputs[0].push_back(x);
      if (exponents.size() > 1) p.inputs[1].push_back(n);
      p.target.push_back(std::pow(x, n));
    }
  }
  return p;
}

SearchOptions enumeration_only(Loss loss) {
  SearchOptions o = test::seed_task_options();
  o.evolve = false;
  o.loss = loss;
  o.threads = 1;
  o.time_limit_s = 120;  // a bound, not an expectation: the level cap stops it
  o.max_enumeration_cost = 4;
  return o;
}

const FrontMember* exact_member(const SearchSummary& s) {
  for (const FrontMember& m : s.front)
    if (m.metrics.max_rel <= 1e-12) return &m;
  return nullptr;
}

TEST(DynamicRange, RelativeAndLogLossesFindAnIntegerPowerOverTwentyDecades) {
  const SearchProblem p = powers({16});  // y from 1.5e-21 to 1
  for (Loss loss : {Loss::Relative, Loss::Log, Loss::Mse}) {
    SearchOptions o = enumeration_only(loss);
    o.max_power = 16;
    SearchSummary s;
    run_search(o, p, &s);
    const FrontMember* m = exact_member(s);
    ASSERT_NE(m, nullptr) << loss_name(loss) << "\n" << s.brief_report();
    EXPECT_EQ(m->formula, "x^16") << loss_name(loss);
    EXPECT_LE(m->cost, 4) << loss_name(loss);
    EXPECT_LE(m->loss, 1e-20) << loss_name(loss);
  }
}

TEST(DynamicRange, RelativeLossOnATailFarBelowTheCandidates) {
  // y = x^16 on [0.01, 1], from 1e-32: there x alone is off by a relative 1e30, whose square
  // overflows float32; the screen counts it as 1e15, so candidates are not all dropped.
  SearchProblem p;
  p.input_names = {"x"};
  p.inputs.assign(1, {});
  for (int i = 0; i <= 256; ++i) {
    const double x = 0.01 + 0.99 * i / 256.0;
    p.inputs[0].push_back(x);
    p.target.push_back(std::pow(x, 16));
  }
  SearchOptions o = enumeration_only(Loss::Relative);
  o.max_power = 16;
  int entered = 0;  // members that joined the front during the search
  o.on_new_member = [&](const FrontMember&) { ++entered; };
  SearchSummary s;
  run_search(o, p, &s);
  const FrontMember* m = exact_member(s);
  ASSERT_NE(m, nullptr) << s.brief_report();
  EXPECT_EQ(m->formula, "x^16");
  EXPECT_GE(entered, 3) << s.brief_report();
  // The final front is tidied: `x^2 - (x^2 + 0.5 - 0.5)` (rounding noise, relative loss 5e27) is
  // the constant 0 (loss 1), which dominates every power below x^16.
  EXPECT_EQ(s.front.front().formula, "0") << s.brief_report();
}

TEST(DynamicRange, PowWithAVariableExponentIsEnumeratedWhenAsked) {
  // y = pow(x, n) from 2.3e-42 (below float32's normal range: those rows leave the float32
  // screens of the rel loss) to 1; for log only up to n = 16 (1.5e-21), as the log loss floors
  // predictions at 1e-30.
  const SearchProblem wide = powers({1, 2, 4, 8, 16, 32}), p = powers({1, 2, 4, 8, 16});
  for (Loss loss : {Loss::Relative, Loss::Log, Loss::MaxAbs, Loss::Mse}) {
    SearchOptions o = enumeration_only(loss);
    o.operators = {Op::Add, Op::Sub, Op::Mul, Op::Div, Op::IPow, Op::Pow};
    o.max_enumeration_cost = 3;
    SearchSummary s;
    run_search(o, loss == Loss::Log ? p : wide, &s);
    const FrontMember* m = exact_member(s);
    ASSERT_NE(m, nullptr) << loss_name(loss) << "\n" << s.brief_report();
    EXPECT_EQ(m->formula, "pow(x, n)") << loss_name(loss);
    EXPECT_EQ(m->cost, 3) << loss_name(loss);  // exp2(n * log2(x)): pow costs 3
    std::printf("%s: %s found after %.1f ms\n", std::string(loss_name(loss)).c_str(),
                m->formula.c_str(), m->time_s * 1e3);
  }
  // Without pow in the operator set the enumeration has no variable exponent.
  SearchOptions o = enumeration_only(Loss::Relative);
  o.max_enumeration_cost = 3;
  SearchSummary s;
  run_search(o, p, &s);
  EXPECT_EQ(exact_member(s), nullptr) << s.brief_report();
}

TEST(DynamicRange, PowOfANegativeBaseNeverEntersTheFront) {
  // pow(a, b) is exp2(b log2 a): NaN for a < 0, as on GPUs. On x in [-1, 1] the screen drops
  // every pow of a class that takes negative values, so the front is x * x, not pow(x, 2).
  SearchProblem p;
  p.input_names = {"x"};
  p.inputs.assign(1, {});
  for (int i = 0; i <= 200; ++i) {
    const double x = -1 + i / 100.0;
    p.inputs[0].push_back(x);
    p.target.push_back(x * x + 0.25);
  }
  SearchOptions o = enumeration_only(Loss::Mse);
  o.operators = {Op::Add, Op::Sub, Op::Mul, Op::Pow};
  SearchSummary s;
  run_search(o, p, &s);
  ASSERT_FALSE(s.front.empty());
  for (const FrontMember& m : s.front) {
    EXPECT_TRUE(std::isfinite(m.loss)) << m.formula;
    EXPECT_EQ(m.formula.find("pow(x,"), std::string::npos) << m.formula;
  }
  EXPECT_LE(s.front.back().metrics.max_abs, 1e-15) << s.brief_report();
}

}  // namespace
}  // namespace shaderfit
