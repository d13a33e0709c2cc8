#include "shaderfit/rational/parametric.hpp"

#include <gtest/gtest.h>

namespace shaderfit::rational {
namespace {

RationalProblem problem_of(const std::string& target, std::vector<std::string> names,
                           std::vector<double> values, const std::vector<std::string>& conditions) {
  RationalProblem p;
  p.target = Target::builtin(target);
  p.parameter_names = std::move(names);
  p.parameter_values = std::move(values);
  p.domain = {0, 1};
  for (const std::string& c : conditions)
    p.conditions.push_back(parse_condition(c, p.parameter_names));
  return p;
}

TEST(RationalParametric, SchlickCoefficientsAreLinearInF0) {
  const RationalProblem p = problem_of(
      "fresnel-dielectric-f0", {"F0"}, {0.04},
      {"f(0) = 1", "f(1) = F0", "f'(1) = 0", "f''(1) = 0", "f'''(1) = 0", "f^(4)(1) = 0"});
  const auto laws =
      parametric_laws({}, p, "F0", {0.02, 0.9},
                      {{5, 0, Transform::reflection(p.domain)}, {5, 0, Transform::identity()}});
  ASSERT_EQ(laws.size(), 2u);
  ASSERT_TRUE(laws[0].all_rational) << laws[0].note;
  EXPECT_EQ(laws[0].coefficients[0].law, "F0");
  EXPECT_EQ(laws[0].coefficients[1].law, "0");
  EXPECT_EQ(laws[0].coefficients[5].law, "1 - F0");
  EXPECT_EQ(laws[0].formula, "F0 + (1 - F0) * (1 - cos)^5");
  // In cos itself the coefficients are linear in F0 too: 1 - 5 (1 - F0) cos + ...
  ASSERT_TRUE(laws[1].all_rational);
  EXPECT_EQ(laws[1].coefficients[0].law, "1");
}

TEST(RationalParametric, SchlickGeometricTermIsRationalInK) {
  // G(0) = 0, G(1) = 1, G'(0) = 1/k: with q0 = 1, p1 = 1/k and q1 = (1 - k)/k; normalised by the
  // numerator instead, Schlick's own v / (k + (1 - k) v) = v / (v - k v + k).
  const RationalProblem p = problem_of("smith-ggx-g1", {"alpha", "k"}, {0.5, 0.25},
                                       {"G(0) = 0", "G(1) = 1", "G'(0) = 1/k"});
  const auto laws = parametric_laws({}, p, "k", {0.05, 0.95}, {{1, 1, Transform::identity()}});
  ASSERT_TRUE(laws[0].all_rational) << laws[0].note;
  ASSERT_EQ(laws[0].coefficients.size(), 4u);
  EXPECT_EQ(laws[0].coefficients[0].law, "0");
  EXPECT_EQ(laws[0].coefficients[1].law, "1");
  EXPECT_EQ(laws[0].coefficients[2].coefficient, "q0");
  EXPECT_EQ(laws[0].coefficients[2].law, "k");
  EXPECT_EQ(laws[0].coefficients[3].law, "1 - k");
  EXPECT_LE(laws[0].coefficients[3].max_deviation, 1e-12);
  EXPECT_EQ(laws[0].formula, "v / (k + (1 - k) * v)");
  // The slope of Smith GGX itself, G'(0) = 2 / alpha, gives Karis's k = alpha / 2.
  const RationalProblem g =
      problem_of("smith-ggx-g1", {"alpha"}, {0.5}, {"G(0) = 0", "G(1) = 1", "G'(0) = ref"});
  const auto ggx = parametric_laws({}, g, "alpha", {0.1, 0.9}, {{1, 1, Transform::identity()}});
  ASSERT_TRUE(ggx[0].all_rational) << ggx[0].note;
  EXPECT_EQ(ggx[0].formula, "v / (0.5 * alpha + (1 - 0.5 * alpha) * v)");
}

TEST(RationalParametric, MinimaxCoefficientsAreNotRational) {
  const RationalProblem p =
      problem_of("fresnel-dielectric-f0", {"F0"}, {0.04}, {"f(0) = 1", "f(1) = F0"});
  RationalOptions o;
  o.fit = Fit::Minimax;
  const auto laws =
      parametric_laws(o, p, "F0", {0.02, 0.2}, {{4, 0, Transform::reflection(p.domain)}});
  ASSERT_TRUE(laws[0].usable) << laws[0].note;
  EXPECT_FALSE(laws[0].all_rational);
  EXPECT_EQ(laws[0].coefficients[0].law, "F0");  // f(1) = F0 is kept exact: p0 = F0
  EXPECT_NE(laws[0].coefficients[2].law.find("not a rational function"), std::string::npos);
}

}  // namespace
}  // namespace shaderfit::rational
