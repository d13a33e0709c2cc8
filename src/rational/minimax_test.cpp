#include <gtest/gtest.h>

#include <cmath>

#include "rational/remez.hpp"
#include "shaderfit/rational/solve.hpp"

namespace shaderfit::rational {
namespace {

FormResult minimax_of(const std::string& target, Interval domain, int m, int n,
                      const std::vector<std::string>& conditions = {},
                      std::vector<std::string> names = {}, std::vector<double> values = {},
                      bool relative = false) {
  RationalProblem p;
  p.target = Target::builtin(target);
  p.parameter_names = std::move(names);
  p.parameter_values = std::move(values);
  p.domain = domain;
  for (const std::string& c : conditions)
    p.conditions.push_back(parse_condition(c, p.parameter_names));
  RationalOptions o;
  o.fit = Fit::Minimax;
  o.relative_minimax = relative;
  return solve_form(o, p, {m, n, Transform::identity()});
}

// The error equioscillates: alternating signs, equal magnitudes, as many points as needed.
void expect_equioscillation(const Equioscillation& e, std::size_t points, double spread) {
  EXPECT_TRUE(e.converged);
  ASSERT_GE(e.points.size(), points);
  for (std::size_t i = 1; i < e.points.size(); ++i) {
    EXPECT_LT(e.points[i - 1], e.points[i]);
    EXPECT_LT(e.errors[i - 1] * e.errors[i], 0.0) << "signs must alternate at " << i;
  }
  for (double err : e.errors) EXPECT_NEAR(std::abs(err), e.max_error, spread * e.max_error);
  EXPECT_LE(e.spread, spread);
  EXPECT_NEAR(e.levelled_error, e.max_error, spread * e.max_error);
}

// Acceptance: a (2, 2) rational minimax of exp on [-1, 1] equioscillates at 2 + 2 + 2 points.
TEST(RationalMinimax, ExpTwoTwoEquioscillates) {
  const FormResult r = minimax_of("exp", {-1, 1}, 2, 2);
  ASSERT_TRUE(r.usable()) << r.message;
  ASSERT_TRUE(r.minimax.has_value());
  expect_equioscillation(*r.minimax, 6, 1e-6);
  EXPECT_EQ(r.minimax->points.size(), 6u);
  EXPECT_NEAR(r.minimax->points.front(), -1.0, 1e-12);
  EXPECT_NEAR(r.minimax->points.back(), 1.0, 1e-12);
  // The best (2, 2) error of exp on [-1, 1] is 8.69e-5; the grid metric agrees with the minimax.
  EXPECT_NEAR(r.minimax->max_error, 8.690e-5, 1e-8);
  EXPECT_NEAR(r.max_abs, r.minimax->max_error, 1e-9);
}

// Polynomial minimax against Sollya's remez (8.0, prec = 200, dirtyinfnorm),
// bench/remez_vs_sollya.sh.
TEST(RationalMinimax, PolynomialsMatchSollya) {
  struct Case {
    const char* target;
    Interval domain;
    int degree;
    double sollya;
  };
  const Case cases[] = {
      {"exp2", {0, 1}, 3, 1.0703434949490895e-4},
      {"log2", {1, 2}, 7, 2.7729071192122351e-7},
      {"atan", {-1, 1}, 3, 4.9519999720792102e-3},
      {"atan", {-1, 1}, 4, 4.9519999720792102e-3},  // odd target: the degree-3 optimum again
  };
  for (const Case& c : cases) {
    const FormResult r = minimax_of(c.target, c.domain, c.degree, 0);
    ASSERT_TRUE(r.usable()) << c.target << " " << c.degree << ": " << r.message;
    // Sollya stops its exchange a little earlier (log2 degree 7: 4e-6 above ours).
    EXPECT_NEAR(r.minimax->max_error, c.sollya, 1e-5 * c.sollya) << c.target << " " << c.degree;
    EXPECT_LE(r.max_abs, c.sollya * 1.000001) << c.target << " " << c.degree;
    expect_equioscillation(*r.minimax, static_cast<std::size_t>(c.degree) + 2, 1e-6);
  }
  EXPECT_TRUE(minimax_of("atan", {-1, 1}, 5, 0).minimax->symmetric);
  EXPECT_EQ(minimax_of("atan", {-1, 1}, 5, 0).rational.p[2], 0.0);
}

// Conditions stay exact: Fresnel through f(0) = 1 and f(1) = F0, minimax of the rest.
TEST(RationalMinimax, KeepsChosenConditionsExact) {
  const FormResult r =
      minimax_of("fresnel-dielectric-f0", {0, 1}, 5, 0, {"f(0) = 1", "f(1) = F0"}, {"F0"}, {0.04});
  ASSERT_TRUE(r.usable()) << r.message;
  EXPECT_NEAR(r.rational(0.0), 1.0, 1e-13);
  EXPECT_NEAR(r.rational(1.0), 0.04, 1e-13);
  expect_equioscillation(*r.minimax, 5, 1e-6);  // 6 coefficients - 2 conditions + 1
  EXPECT_LT(r.max_abs, 4e-3);
  // Rational with conditions, relative error.
  const FormResult q = minimax_of("fresnel-dielectric-f0", {0, 1}, 2, 1, {"f(0) = 1", "f(1) = F0"},
                                  {"F0"}, {0.04}, /*relative=*/true);
  ASSERT_TRUE(q.usable()) << q.message;
  EXPECT_NEAR(q.rational(1.0), 0.04, 1e-13);
  expect_equioscillation(*q.minimax, 3, 1e-6);
  EXPECT_TRUE(q.minimax->relative);
}

TEST(RationalMinimax, ChooseReferenceKeepsAlternationAndTheLargest) {
  using rational_detail::Extremum;
  const std::vector<Extremum> c = {{0, 1}, {1, 0.5}, {2, -2}, {3, 0.1}, {4, -0.2}, {5, 3}, {6, -1}};
  const auto r = rational_detail::choose_reference(c, 4);
  ASSERT_EQ(r.size(), 4u);
  for (std::size_t i = 1; i < r.size(); ++i) EXPECT_LT(r[i - 1].e * r[i].e, 0);
  bool has_max = false;
  for (const Extremum& e : r) has_max = has_max || e.e == 3;
  EXPECT_TRUE(has_max);
  EXPECT_TRUE(rational_detail::choose_reference({{0, 1}, {1, 2}}, 2).empty());
}

}  // namespace
}  // namespace shaderfit::rational
