// Shading shapes as starts (search/starts/shape_starts.hpp): products of separately searched
// factors, Schlick-like factors, powers of linear forms, per-material coefficients.
#include "search/starts/shape_starts.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "search/run/drawn_problem_test_util.hpp"
#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/expr/print.hpp"
#include "shaderfit/fit/fit.hpp"

namespace shaderfit::search_detail {
namespace {

using V = std::vector<double>;

SearchProblem problem_of(const std::string& text, const std::vector<std::string>& names,
                         const std::vector<std::pair<double, double>>& ranges) {
  const Expression e = parse_formula(text, {.variables = names});
  return test::drawn_problem(
      names, ranges, [&](const V& row) { return evaluate_scalar(e, row); }, 7, 3000);
}

using test::relative_rms;

// The least relative RMS error among the shapes costing at most `cost`.
double best_at(const std::vector<StartFormula>& shapes, const SearchOptions& o,
               const SearchProblem& p, double cost) {
  double best = HUGE_VAL;
  for (const StartFormula& s : shapes) {
    EXPECT_EQ(s.origin, SearchPhase::Shape);
    EXPECT_TRUE(s.fitted);
    if (formula_cost(s.free, o) <= cost) best = std::min(best, relative_rms(s.free, p));
  }
  return best;
}

// A product of a Schlick-like factor of x and an exponential of y: each factor is one of the
// one-input shapes, so their product, refitted together, is the function.
TEST(ShapeStarts, AProductOfSeparateFactorsIsFound) {
  const std::vector<std::string> names = {"x", "y"};
  const SearchProblem p =
      problem_of("(1 + 3 * (1 - x)^5) * exp2(1.5 * y)", names, {{0, 1}, {0, 1}});
  SearchOptions o;
  SearchContext ctx(o, p);
  const std::vector<StartFormula> shapes = shape_starts(ctx, 1e9);
  ASSERT_FALSE(shapes.empty());
  EXPECT_LT(best_at(shapes, o, p, 1e9), 1e-4);
}

// Henyey-Greenstein with g per material is m0 (1 + m1 c)^p with coefficients of g: the power of a
// linear form, 4 instructions per pixel (the scale moved into the exponential).
TEST(ShapeStarts, APowerOfALinearFormWithPerMaterialCoefficients) {
  const std::vector<std::string> names = {"c", "g"};
  const SearchProblem p = problem_of("(1 - g^2) / pow(1 + g^2 - 2 * g * c, 1.5) / 12.566371", names,
                                     {{-1, 1}, {0, 0.9}});
  SearchOptions o;
  o.uniform = {"g"};
  SearchContext ctx(o, p);
  const std::vector<StartFormula> shapes = shape_starts(ctx, 1e9);
  EXPECT_LT(best_at(shapes, o, p, 4), 1e-3);
}

// Eight inputs, two per material (fuzz4's HDRP V_SmithJointGGXAniso): a product of six
// one-input factors has more parameters than a fit takes once each gains a coefficient per
// material; the shapes stay within kMaxFitParameters instead of failing the search.
TEST(ShapeStarts, PerMaterialCoefficientsStayWithinWhatAFitTakes) {
  const std::vector<std::string> names = {"a", "b", "c", "d", "e", "f", "u", "v"};
  std::vector<std::pair<double, double>> ranges(names.size(), {0.05, 1.0});
  const SearchProblem p = problem_of(
      "0.5 / (c * sqrt((u * a)^2 + (v * b)^2 + c^2) + f * sqrt((u * d)^2 + (v * e)^2 + f^2))",
      names, ranges);
  SearchOptions o;
  o.uniform = {"u", "v"};
  SearchContext ctx(o, p);
  std::vector<StartFormula> shapes;
  ASSERT_NO_THROW(shapes = shape_starts(ctx, 1e9));
  for (const StartFormula& s : shapes) EXPECT_LE(s.free.parameters.size(), kMaxFitParameters);
}

TEST(ShapeStarts, NoneForATargetThatIsNotPositive) {
  const SearchProblem p = problem_of("x - 0.5", {"x"}, {{0, 1}});
  SearchOptions o;
  SearchContext ctx(o, p);
  EXPECT_TRUE(shape_starts(ctx, 1e9).empty());
}

TEST(ShapeStarts, TheSameShapesForTheSameRows) {
  const SearchProblem p = problem_of("1 / (1 + 2 * x * y) + 0.25", {"x", "y"}, {{0, 1}, {0, 1}});
  SearchOptions o;
  SearchContext a(o, p), b(o, p);
  const std::vector<StartFormula> first = shape_starts(a, 1e9), second = shape_starts(b, 1e9);
  ASSERT_EQ(first.size(), second.size());
  for (std::size_t k = 0; k < first.size(); ++k)
    EXPECT_EQ(to_infix(first[k].free), to_infix(second[k].free));
}

}  // namespace
}  // namespace shaderfit::search_detail
