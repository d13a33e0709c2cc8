// The largest error between the samples.
#include "shaderfit/verify/worst_case.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "shaderfit/core/error.hpp"
#include "shaderfit/expr/parse.hpp"
#include "verify/reference_test_util.hpp"

namespace shaderfit {
namespace {

using test::make_reference;

Expression formula(const std::string& text, const std::vector<std::string>& inputs) {
  ParseOptions o;
  o.variables = inputs;
  return parse_formula(text, o);
}

// The largest |f - g| on a uniform grid of n points of [lo, hi].
double grid_max(const std::function<double(double)>& e, double lo, double hi, int n) {
  double worst = 0;
  for (int i = 0; i < n; ++i) worst = std::max(worst, std::abs(e(lo + (hi - lo) * i / (n - 1))));
  return worst;
}

TEST(WorstCase, FindsThePeakBetweenCoarseSamples) {
  // 11 samples of [0, 1]: sin(10 x) peaks between them; the check with its local search finds
  // the true maximum of |sin(10 x) - 0| = 1 (at x = pi/20 and others).
  const reference::ReferenceFunction f = make_reference("sin(10 * x)", {"x=0:1"});
  WorstCaseOptions o;
  o.samples = 11;
  const WorstCaseSearch w(f, {"x"}, o);
  const WorstCase c = w.check(formula("0", {"x"}));
  EXPECT_TRUE(c.finite);
  EXPECT_NEAR(c.max_abs, 1.0, 1e-12);
  ASSERT_EQ(c.worst_abs.point.size(), 1u);
  EXPECT_NEAR(std::abs(std::sin(10 * c.worst_abs.point[0])), 1.0, 1e-12);
  EXPECT_GT(c.points.size(), 1u);
  for (std::size_t i = 1; i < c.points.size(); ++i)
    EXPECT_GE(c.points[i - 1].abs_error, c.points[i].abs_error);  // worst first
}

TEST(WorstCase, NeverBelowADenseGridOnAnAcosApproximation) {
  // Abramowitz and Stegun 4.4.45 on [0, 1]: equioscillating, peaks of nearly equal height.
  const reference::ReferenceFunction f = make_reference("acos(x)", {"x=0:1"});
  const std::string as = "sqrt(1 - x)*(1.5707288 + x*(-0.2121144 + x*(0.0742610 - 0.0187293*x)))";
  const WorstCaseSearch w(f, {"x"}, {.samples = 1001});
  const WorstCase c = w.check(formula(as, {"x"}));
  const double dense = grid_max(
      [](double x) {
        return std::sqrt(1 - x) * (1.5707288 + x * (-0.2121144 + x * (0.0742610 - 0.0187293 * x))) -
               std::acos(x);
      },
      0, 1, 1000001);
  EXPECT_GE(c.max_abs, dense * (1 - 1e-12));
  EXPECT_LE(c.max_abs, dense * 1.01);
  EXPECT_TRUE(std::isfinite(c.max_rel));
  EXPECT_GT(c.float32_max_abs, 0);
}

TEST(WorstCase, TwoVariablesWithADefinitionAsInput) {
  // The formula reads a definition (t = x * y), the check moves in the domain (x, y).
  const reference::ReferenceFunction f =
      make_reference("exp(-t)", {"x=0:1", "y=0:2"}, {"t = x * y"});
  const WorstCaseSearch w(f, {"t"}, {.samples = 256});
  const WorstCase c = w.check(formula("1 - t + 0.5 * t^2", {"t"}));
  // The error grows with t; its maximum is at the corner x = 1, y = 2 (t = 2).
  const double exact = std::abs(1 - 2 + 2 - std::exp(-2.0));
  EXPECT_NEAR(c.max_abs, exact, 1e-12);
  ASSERT_EQ(c.worst_abs.point.size(), 2u);
  EXPECT_DOUBLE_EQ(c.worst_abs.point[0], 1.0);
  EXPECT_DOUBLE_EQ(c.worst_abs.point[1], 2.0);
}

TEST(WorstCase, AFormulaNaNBetweenTheSamplesIsNotFinite) {
  // log(x - 0.3) is NaN on [0, 0.3]: not finite, and a point there is reported.
  const reference::ReferenceFunction f = make_reference("x", {"x=0:1"});
  const WorstCaseSearch w(f, {"x"}, {.samples = 11});
  const WorstCase c = w.check(formula("log(x + 0.05) + 1", {"x"}));
  EXPECT_TRUE(c.finite);
  const WorstCase bad = w.check(formula("sqrt(x - 0.3)", {"x"}));
  EXPECT_FALSE(bad.finite);
  EXPECT_TRUE(std::isinf(bad.max_abs));
  ASSERT_FALSE(bad.points.empty());
  EXPECT_LT(bad.worst_abs.point[0], 0.3);
}

TEST(WorstCase, RefineClimbsToAPoleNearAPoint) {
  // A pole along x + y = 1.2345678 with a tiny residue: far from it the error is about 1e-9;
  // refined from a point near the line it blows up.
  const reference::ReferenceFunction f = make_reference("x + y", {"x=0:1", "y=0:1"});
  const WorstCaseSearch w(f, {"x", "y"}, {.samples = 256});
  const Expression e = formula("x + y + 1e-9 / (x + y - 1.2345678)", {"x", "y"});
  const ErrorPoint far = w.refine(e, std::vector<double>{0.1, 0.1});
  EXPECT_LT(far.abs_error, 1e-8);
  const ErrorPoint near = w.refine(e, std::vector<double>{0.6, 0.6345});
  EXPECT_GT(near.abs_error, 1e-3);
  EXPECT_NEAR(near.point[0] + near.point[1], 1.2345678, 1e-6);
}

// A grid given by counts is refined about `density` times in all, however many its axes: 8
// axes of 4 points (65,536) get 5 each (390,625), not 8 each (16.8 million).
TEST(WorstCase, AGridOfManyAxesIsRefinedAboutDensityTimes) {
  std::vector<std::string> axes;
  std::string sum = "0";
  for (const char* v : {"a", "b", "c", "d", "e", "f", "g", "h"}) {
    axes.push_back(std::string(v) + "=0:1:4");
    sum += std::string(" + ") + v;
  }
  const reference::ReferenceFunction f = make_reference(sum, axes);
  const WorstCaseSearch w(f, {"a"}, {.samples = 0, .density = 10, .threads = 1});
  EXPECT_EQ(w.dense_points(), 390625u);
  const reference::ReferenceFunction g = make_reference("x * y", {"x=0:1:50", "y=0:1:40"});
  EXPECT_EQ(WorstCaseSearch(g, {"x", "y"}, {.density = 10}).dense_points(), 158u * 126u);
}

TEST(WorstCase, ChecksItsInputs) {
  const reference::ReferenceFunction f = make_reference("x", {"x=0:1"});
  EXPECT_THROW(WorstCaseSearch(f, {"nope"}), Error);
  const WorstCaseSearch w(f, {"x"}, {.samples = 11});
  EXPECT_THROW((void)w.check(formula("y", {"y"})), Error);
}

}  // namespace
}  // namespace shaderfit
