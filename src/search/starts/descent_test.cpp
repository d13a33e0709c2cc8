// Downward from the reference (search/starts/descent.hpp): the rewrites are cheaper and keep
// what they claim; the descent finds the exact cheaper forms a person writes by hand.
#include "search/evolution/rewrites.hpp"
#include "search/starts/descent.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "search/run/drawn_problem_test_util.hpp"
#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/expr/print.hpp"
#include "search/starts/start.hpp"

namespace shaderfit::search_detail {
namespace {

using V = std::vector<double>;

Expression formula(const std::string& text, const std::vector<std::string>& names) {
  return parse_formula(text, {.variables = names});
}

// The problem of `text` over `names` on the ranges, its reference formula the target.
SearchProblem problem_of(const std::string& text, const std::vector<std::string>& names,
                         const std::vector<std::pair<double, double>>& ranges, int rows = 3000) {
  const Expression e = formula(text, names);
  return test::drawn_problem(
      names, ranges, [&](const V& row) { return evaluate_scalar(e, row); }, 5, rows);
}

using test::relative_rms;

TEST(Descent, RewritesAreCheaperAndFinite) {
  const std::vector<std::string> names = {"x", "y"};
  const SearchProblem p = problem_of("saturate(1 - x)^5 * (y + 0.5) + max(y, 0.001)", names,
                                     {{0, 1}, {0.1, 1}});
  SearchOptions o;
  const Expression e = formula("saturate(1 - x)^5 * (y + 0.5) + max(y, 0.001)", names);
  const double cost = formula_cost(e, o);
  const std::vector<Expression> rewrites = cheaper_rewrites(e, o, descent_rows(p));
  ASSERT_FALSE(rewrites.empty());
  bool exact = false;
  for (const Expression& r : rewrites) {
    EXPECT_LT(formula_cost(r, o), cost) << to_infix(r);
    // Dropping the saturate and the max, neither of which binds on the rows, is exact.
    if (relative_rms(r, p) < 1e-12) exact = true;
  }
  EXPECT_TRUE(exact);
}

TEST(Descent, SharedLiteralsKeepRepeatedPartsOne) {
  SearchOptions o;
  const Expression e =
      formula("(1 + 2 * (1 - x)^2) * (1 + 2 * (1 - x)^2 * y) * 0.5", {"x", "y"});
  const Expression free = with_shared_literal_parameters(e);
  EXPECT_EQ(formula_cost(free, o), formula_cost(e, o));
  EXPECT_FALSE(free.parameters.empty());
  for (std::size_t k = 0; k < free.parameters.size(); ++k) SCOPED_TRACE(free.parameters[k]);
  EXPECT_DOUBLE_EQ(evaluate_scalar(free, V{0.3, 0.7}), evaluate_scalar(e, V{0.3, 0.7}));
}

// Henyey-Greenstein with g per material: (1 - g^2) / (4 pi) rsqrt(d)^3 with d = 1 + g^2 - 2 g c is
// exp2(log2((1 - g^2) / (4 pi)) - 1.5 log2(d)): 4 instructions per pixel, exact, one rewrite
// below the function as its shader writes it (7).
TEST(Descent, HenyeyGreensteinPerMaterialIsAPowerOfALinearForm) {
  const std::vector<std::string> names = {"c", "g"};
  const std::string text =
      "(1 - g^2) * rsqrt(max(1 + g^2 - 2 * g * c, 1e-6)) * rsqrt(max(1 + g^2 - 2 * g * c, "
      "1e-6)) * rsqrt(max(1 + g^2 - 2 * g * c, 1e-6)) / 12.566371";
  const SearchProblem p = problem_of(text, names, {{-1, 1}, {0, 0.9}});
  SearchOptions o;
  o.uniform = {"g"};
  const Expression e = formula(text, names);
  EXPECT_EQ(formula_cost(e, o), 7);
  double best = HUGE_VAL;
  for (const Expression& r : cheaper_rewrites(e, o, descent_rows(p)))
    if (formula_cost(r, o) <= 4)
      best = std::min(best, relative_rms(refit_for_loss(with_shared_literal_parameters(r), o, p), p));
  EXPECT_LT(best, 1e-9);
}

// Products regrouped by the inputs their factors read: (1 - x)^5 in t (1 - x)^2 (1 - x)^2 (1 - x)
// becomes one part, which the fitted forms of one input replace (Burley's diffuse, one side).
TEST(Descent, RegroupedProductsExposeAPartOfOneInput) {
  const std::vector<std::string> names = {"x", "r"};
  const std::string text = "1 + (r - 0.5) * (1 - x) * (1 - x) * ((1 - x) * (1 - x)) * (1 - x)";
  const SearchProblem p = problem_of(text, names, {{0, 1}, {0, 1}});
  SearchOptions o;
  const Expression e = formula(text, names);
  bool exp2_of_x = false;
  for (const Expression& r : cheaper_rewrites(e, o, descent_rows(p))) {
    const std::string s = to_infix(r);
    if (s.find("exp2(") != std::string::npos && s.find("(1 - x)") == std::string::npos &&
        relative_rms(refit_for_loss(with_shared_literal_parameters(r), o, p), p) < 0.1)
      exp2_of_x = true;
  }
  EXPECT_TRUE(exp2_of_x);
}

}  // namespace
}  // namespace shaderfit::search_detail
