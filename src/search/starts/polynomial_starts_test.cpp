// Polynomial starts (search/polynomial_starts.hpp): one input only, fitted for the loss, the
// symmetric shapes where the data has a symmetry.
#include "search/starts/polynomial_starts.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "search/run/drawn_problem_test_util.hpp"
#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/eval/metrics.hpp"
#include "shaderfit/expr/parse.hpp"

namespace shaderfit::search_detail {
namespace {

using V = std::vector<double>;

SearchProblem one_input(double lo, double hi, double (*f)(double), int rows = 3000) {
  return test::drawn_problem(
      {"t"}, {{lo, hi}}, [f](const V& x) { return f(x[0]); }, 5, rows);
}

ErrorMetrics metrics_of(const std::string& text, const SearchProblem& p) {
  const Expression e = parse_formula(text, {.variables = {"x0"}});
  V f(p.target.size());
  evaluate(e, std::vector<const double*>{p.inputs[0].data()}, f, {.threads = 1});
  return error_metrics(f, p.target, {}, p.weights);
}

TEST(PolynomialStarts, OneInputOnly) {
  const SearchProblem two = test::drawn_problem(
      {"a", "b"}, {{0, 1}, {0, 1}}, [](const V& x) { return x[0] * x[1]; }, 3, 500);
  EXPECT_TRUE(polynomial_starts(two, std::nullopt, Loss::MaxAbs).empty());
  const SearchProblem p = one_input(0, 2, [](double x) { return std::exp(x); });
  const auto texts = polynomial_starts(p, std::nullopt, Loss::MaxAbs);
  EXPECT_EQ(texts.size(), static_cast<std::size_t>(kPolynomialMaxDegree - 1));  // degrees 2..10
  // Each degree fits better than the one before (minimax on the rows read, checked on all).
  double previous = INFINITY;
  for (const std::string& t : texts) {
    const double e = metrics_of(t, p).max_abs;
    EXPECT_LT(e, previous) << t;
    previous = e;
  }
  EXPECT_LT(previous, 1e-9);
}

TEST(PolynomialStarts, FittedForTheLoss) {
  const SearchProblem p = one_input(0, 1, [](double x) { return std::atan(x); });
  const auto minimax = polynomial_starts(p, std::nullopt, Loss::MaxAbs);
  const auto squares = polynomial_starts(p, std::nullopt, Loss::Mse);
  ASSERT_EQ(minimax.size(), squares.size());
  for (std::size_t k = 0; k < minimax.size(); ++k) {
    const ErrorMetrics m = metrics_of(minimax[k], p), s = metrics_of(squares[k], p);
    EXPECT_LT(m.max_abs, s.max_abs) << minimax[k];
    EXPECT_LE(s.mse, m.mse) << squares[k];
  }
  // max_rel weighs by 1 / |y|: near 0 the relative error stays small.
  const auto relative = polynomial_starts(p, std::nullopt, Loss::MaxRel);
  EXPECT_LT(metrics_of(relative[3], p).max_rel, metrics_of(minimax[3], p).max_rel);
}

TEST(PolynomialStarts, SymmetricShapes) {
  const SearchProblem p = one_input(0, 1, [](double x) { return std::atan(x); });
  const DataSymmetry odd{0, "t", SymmetryKind::Odd, 0};
  const auto texts = polynomial_starts(p, odd, Loss::MaxAbs);
  ASSERT_EQ(texts.size(),
            static_cast<std::size_t>(kPolynomialMaxDegree - 1 + kSymmetricMaxTerms - 1));
  // x P(x^2) with 6 terms: the odd minimax of degree 11 on [-1, 1] (max |err| 1.66e-6, less
  // than Eberly's published 2.55e-6 with its leading 1 fixed).
  const std::string& six = texts[kPolynomialMaxDegree - 1 + 4];
  EXPECT_EQ(six.rfind("x0 * (", 0), 0U) << six;
  EXPECT_LT(metrics_of(six, p).max_abs, 1.7e-6) << six;
  const Expression e = parse_formula(six, {.variables = {"x0"}});
  EXPECT_TRUE(symmetric_as_written(e, {0, "x0", SymmetryKind::Odd, 0}));

  const SearchProblem c = one_input(0, 2, [](double x) { return std::cos(x); });
  for (const std::string& t :
       polynomial_starts(c, DataSymmetry{0, "t", SymmetryKind::Even, 0}, Loss::MaxAbs)) {
    if (t.find("x0^2") != std::string::npos) {
      EXPECT_TRUE(symmetric_as_written(parse_formula(t, {.variables = {"x0"}}),
                                       {0, "x0", SymmetryKind::Even, 0}))
          << t;
    }
  }
  // Point-symmetric about m: c + x P(x^2), c fitted (acos(0) = pi/2).
  const SearchProblem a = one_input(0, 0.9, [](double x) { return std::acos(x); });
  const auto point =
      polynomial_starts(a, DataSymmetry{0, "t", SymmetryKind::Point, M_PI / 2, -1}, Loss::MaxAbs);
  const std::string& last = point.back();
  EXPECT_NE(last.find(" + x0 * ("), std::string::npos) << last;
  EXPECT_NEAR(std::stod(last), M_PI / 2, 1e-3) << last;
}

}  // namespace
}  // namespace shaderfit::search_detail
