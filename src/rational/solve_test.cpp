#include "shaderfit/rational/solve.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "shaderfit/core/error.hpp"
#include "shaderfit/rational/rational_setup.hpp"

namespace shaderfit::rational {
namespace {

RationalProblem problem_of(const std::string& target, std::vector<std::string> names,
                           std::vector<double> values, Interval domain,
                           const std::vector<std::string>& conditions) {
  RationalProblem p;
  p.target = Target::builtin(target);
  p.parameter_names = std::move(names);
  p.parameter_values = std::move(values);
  p.domain = domain;
  for (std::size_t i = 0; i < conditions.size(); ++i)
    p.conditions.push_back(
        parse_condition(conditions[i], p.parameter_names,
                        {"RationalProblem::conditions", static_cast<int>(i) + 1, 0}));
  return p;
}

const std::vector<std::string> kSchlick = {"f(0) = 1",   "f(1) = F0",   "f'(1) = 0",
                                           "f''(1) = 0", "f'''(1) = 0", "f^(4)(1) = 0"};

// Acceptance: F(0) = 1, F(1) = F0, F^(k)(1) = 0 for k = 1..4 and a quintic in cos give Schlick's
// F0 + (1 - F0)(1 - cos)^5, for any F0.
TEST(RationalSolve, SchlickFresnelFromItsKernelConditions) {
  for (double f0 : {0.02, 0.04, 0.1, 0.5, 0.9}) {
    RationalProblem p = problem_of("fresnel-dielectric-f0", {"F0"}, {f0}, {0, 1}, kSchlick);
    for (const Transform& t : {Transform::identity(), Transform::reflection(p.domain)}) {
      const FormResult r = solve_form({}, p, {5, 0, t});
      ASSERT_TRUE(r.usable()) << r.message;
      for (double c = 0; c <= 1.0; c += 1.0 / 64)
        EXPECT_NEAR(r.rational(c), f0 + (1 - f0) * std::pow(1 - c, 5), 1e-13)
            << "F0 " << f0 << " cos " << c;
      if (!t.is_identity()) {
        // In 1 - cos the coefficients are exactly F0, 0, 0, 0, 0, 1 - F0: the printed formula is
        // Schlick's, and it costs 5 instructions (1 - cos, t^5 in 3 multiplies, one FMA).
        EXPECT_EQ(r.rational.p, (std::vector<double>{f0, 0, 0, 0, 0, 1 - f0})) << "F0 " << f0;
        EXPECT_EQ(r.cost, 5);
      }
    }
  }
  RationalProblem p = problem_of("fresnel-dielectric-f0", {"F0"}, {0.04}, {0, 1}, kSchlick);
  const FormResult r = solve_form({}, p, {5, 0, Transform::reflection(p.domain)});
  EXPECT_EQ(r.formula, "0.04 + 0.96 * (1 - cos)^5");
  EXPECT_NEAR(r.max_abs, 0.0357, 5e-4);  // Schlick against the exact dielectric Fresnel, IOR 1.5
}

// solve reports the forms solved; solve_prepared the forms of the whole sweep.
TEST(RationalSolve, ReportsFormsSolvedOverTheSweep) {
  RationalSetup s;
  s.target = "fresnel-dielectric-f0";
  s.parameters = {"F0=0.04,0.2,0.5"};
  s.forms = {"5/0"};
  s.transforms = {"1 - cos", "cos"};  // two forms per value
  s.conditions = {"f(0)=1", "f(1)=F0", "f'(1)=0", "f''(1)=0", "f'''(1)=0", "f^(4)(1)=0"};
  PreparedRational r = prepare_rational(s);
  std::vector<std::size_t> seen;
  r.options.on_progress = [&](const Progress& p) {
    EXPECT_EQ(p.total, 6u);
    EXPECT_EQ(p.unit, "forms");
    seen.push_back(p.done);
  };
  (void)solve_prepared(r);
  EXPECT_EQ(seen, (std::vector<std::size_t>{1, 2, 3, 4, 5, 6}));
}

// Acceptance: Schlick's geometric attenuation v / (v - k v + k) from G(0) = 0, G(1) = 1 and the
// slope G'(0) = 1/k, for a linear over linear form; with G'(0) taken from Smith GGX G1 itself
// (2 / alpha) it is Karis's k = alpha / 2.
TEST(RationalSolve, SchlickGeometricAttenuation) {
  for (double k : {0.05, 0.2, 0.5, 0.8}) {
    RationalProblem p = problem_of("smith-ggx-g1", {"alpha", "k"}, {2 * k, k}, {0, 1},
                                   {"G(0) = 0", "G(1) = 1", "G'(0) = 1/k"});
    const FormResult r = solve_form({}, p, {1, 1, Transform::identity()});
    ASSERT_TRUE(r.usable()) << r.message;
    for (double v = 0; v <= 1.0; v += 1.0 / 32)
      EXPECT_NEAR(r.rational(v), v / (v - k * v + k), 1e-14) << k;
    // ... and that is Smith GGX's own slope at 0 when alpha = 2k.
    RationalProblem q = problem_of("smith-ggx-g1", {"alpha"}, {2 * k}, {0, 1},
                                   {"G(0) = 0", "G(1) = 1", "G'(0) = ref"});
    const FormResult s = solve_form({}, q, {1, 1, Transform::identity()});
    for (double v = 0; v <= 1.0; v += 1.0 / 32)
      EXPECT_NEAR(s.rational(v), v / (v - k * v + k), 1e-13) << k;
  }
}

TEST(RationalSolve, EnumeratesEveryFormAndRanksThem) {
  RationalProblem p = problem_of("fresnel-dielectric-f0", {"F0"}, {0.04}, {0, 1},
                                 {"f(0) = 1", "f(1) = F0", "f'(1) = ref", "int(0, 1) = ref"});
  RationalSummary s;
  solve({}, p, &s);
  ASSERT_EQ(s.results.size(), 8u);  // 3/0, 2/1, 1/2, 0/3 in cos and in 1 - cos
  std::size_t usable = 0;
  for (std::size_t i = 0; i < s.results.size(); ++i) {
    const FormResult& r = s.results[i];
    if (!r.usable()) continue;
    ++usable;
    if (i > 0 && s.results[i - 1].usable()) {
      EXPECT_LE(s.results[i - 1].rmse, r.rmse);
    }
    EXPECT_GT(r.cost, 0);
    EXPECT_NEAR(r.rational(0.0), 1.0, 1e-9) << r.formula;
    EXPECT_NEAR(r.rational(1.0), 0.04, 1e-9) << r.formula;
  }
  EXPECT_GE(usable, 3u);
  ASSERT_FALSE(s.pareto.empty());
  for (std::size_t k = 1; k < s.pareto.size(); ++k) {
    EXPECT_LT(s.results[s.pareto[k - 1]].cost, s.results[s.pareto[k]].cost);
    EXPECT_GT(s.results[s.pareto[k - 1]].rmse, s.results[s.pareto[k]].rmse);
  }
  EXPECT_NE(s.full_report().find("Pareto"), std::string::npos) << s.full_report();
}

TEST(RationalSolve, IntegralConditionsBySolvingNonlinearSystems) {
  // exp on [0, 1]: f(0) = 1, f(1) = e, int(0, 1) = e - 1 with a 1/1 form.
  RationalProblem p =
      problem_of("exp", {}, {}, {0, 1}, {"f(0) = ref", "f(1) = ref", "int(0, 1) = ref"});
  const FormResult r = solve_form({}, p, {1, 1, Transform::identity()});
  ASSERT_TRUE(r.usable()) << r.message;
  EXPECT_NEAR(r.rational(0.0), 1.0, 1e-10);
  EXPECT_NEAR(r.rational(1.0), std::exp(1.0), 1e-10);
  double integral = 0;
  for (int i = 0; i < 2000; ++i) integral += r.rational((i + 0.5) / 2000) / 2000;
  EXPECT_NEAR(integral, std::exp(1.0) - 1, 1e-7);
  EXPECT_LT(r.max_abs, 0.05);
}

TEST(RationalSolve, SingularAndPoleForms) {
  // f(0) = 1 twice: no second equation.
  RationalProblem p = problem_of("exp", {}, {}, {0, 1}, {"f(0) = 1", "f(0) = 1"});
  EXPECT_EQ(solve_form({}, p, {1, 0, Transform::identity()}).status, FormStatus::Singular);
  // 1 / (1 + q1 x) through f(0) = 1 and f(1) = -1 needs q1 = -2: a pole at x = 1/2.
  RationalProblem q = problem_of("exp", {}, {}, {0, 1}, {"f(0) = 1", "f(1) = -1"});
  const FormResult r = solve_form({}, q, {0, 1, Transform::identity()});
  EXPECT_EQ(r.status, FormStatus::PoleInDomain);
  EXPECT_NE(r.message.find("x = 0.5"), std::string::npos) << r.message;
}

TEST(RationalSolve, CountMismatchAndDomainErrors) {
  RationalProblem p = problem_of("exp", {}, {}, {0, 1}, {"f(0) = 1", "f(1) = 2", "f'(0) = 1"});
  EXPECT_THROW((void)solve_form({}, p, {1, 0, Transform::identity()}),
               Error);  // 3 conditions, 2 coefficients
  EXPECT_THROW((void)solve_form({}, p, {3, 0, Transform::identity()}),
               Error);  // 3 conditions, 4 coefficients
  RationalOptions lsq;
  lsq.fit = Fit::LeastSquares;
  EXPECT_TRUE(solve_form(lsq, p, {1, 0, Transform::identity()}).usable());
  EXPECT_TRUE(solve_form(lsq, p, {4, 0, Transform::identity()}).usable());
  RationalProblem out = problem_of("exp", {}, {}, {0, 1}, {"f(0) = 1", "f(1.5) = 2"});
  try {
    (void)solve_form({}, out, {1, 0, Transform::identity()});
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.where().line, 2);
    EXPECT_EQ(e.where().column, 3);
    EXPECT_NE(e.message().find("outside the domain [0, 1]"), std::string::npos) << e.what();
  }
}

TEST(RationalSolve, RanksByRmseMaxAbsOrMaxRelOnly) {
  RationalProblem p = problem_of("exp", {}, {}, {0, 1}, {"f(0) = 1", "f(1) = 2"});
  RationalOptions o;
  o.rank_by = Loss::MaxRel;
  RationalSummary s;
  solve(o, p, &s);
  ASSERT_FALSE(s.results.empty());
  EXPECT_EQ(s.results.front().error(Loss::MaxRel), s.results.front().max_rel);
  o.rank_by = Loss::Mse;
  std::string why;
  EXPECT_FALSE(o.is_valid(&why));
  EXPECT_NE(why.find("rank_by"), std::string::npos) << why;
  EXPECT_THROW(solve(o, p, &s), Error);
  EXPECT_THROW((void)s.results.front().error(Loss::Log), Error);
}

TEST(RationalSolve, LeastSquaresKeepsConditionsExact) {
  RationalProblem p =
      problem_of("fresnel-dielectric-f0", {"F0"}, {0.04}, {0, 1}, {"f(0) = 1", "f(1) = F0"});
  RationalOptions o;
  o.fit = Fit::LeastSquares;
  const FormResult r = solve_form(o, p, {4, 1, Transform::reflection(p.domain)});
  ASSERT_TRUE(r.usable()) << r.message;
  EXPECT_NEAR(r.rational(0.0), 1.0, 1e-9);
  EXPECT_NEAR(r.rational(1.0), 0.04, 1e-9);
  const FormResult schlick = [&] {
    RationalProblem s = problem_of("fresnel-dielectric-f0", {"F0"}, {0.04}, {0, 1}, kSchlick);
    return solve_form({}, s, {5, 0, Transform::reflection(s.domain)});
  }();
  EXPECT_LT(r.rmse, schlick.rmse / 5);
}

// The setup takes targets in the reference language and a domain as x=lo:hi; Taylor conditions
// at a point then give the analytic Taylor polynomial.
TEST(RationalSolve, SetupTakesReferenceLanguageTargets) {
  RationalSetup s;
  s.target = "erf(x)";
  s.domain = "x=0:1";
  s.forms = {"3/0"};
  s.conditions = {"f(0)=ref", "f'(0)=ref", "f''(0)=ref", "f'''(0)=ref"};
  PreparedRational r = prepare_rational(s);
  EXPECT_EQ(r.problem.domain.lo, 0.0);
  EXPECT_EQ(r.problem.domain.hi, 1.0);
  const RationalReport report = solve_prepared(r);
  const FormResult& f = report.runs[0].summary.results[0];
  ASSERT_TRUE(f.usable()) << f.message;
  const double c = 2 / std::sqrt(std::numbers::pi);  // erf(x) = c (x - x^3 / 3 + ...)
  EXPECT_NEAR(f.rational.p[0], 0.0, 1e-15);
  EXPECT_NEAR(f.rational.p[1], c, 1e-15);
  EXPECT_NEAR(f.rational.p[2], 0.0, 1e-15);
  EXPECT_NEAR(f.rational.p[3], -c / 3, 1e-15);
  // The domain's variable must be the target's; a count has no use.
  s.domain = "t=0:1";
  EXPECT_THROW((void)prepare_rational(s), Error);
  s.domain = "x=0:1:10";
  EXPECT_THROW((void)prepare_rational(s), Error);
  // A bare name of a reference function is not a built-in target: the message says how.
  s.domain = "0,1";
  s.target = "erf";
  try {
    (void)prepare_rational(s);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.where().source, "RationalSetup::target");
    EXPECT_NE(e.message().find("erf(x)"), std::string::npos) << e.message();
  }
  // A shader function with a parameter given a value.
  RationalSetup g;
  g.reference_source =
      "float schlick(float f0, float c) { float m = 1.0 - c; return mix(f0, 1.0, m*m*m*m*m); }";
  g.reference_path = "schlick.hlsl";
  g.function = "schlick";
  g.parameters = {"f0=0.04"};
  g.forms = {"5/0"};
  g.transforms = {"1 - c"};
  g.conditions = {"f(0)=1", "f(1)=f0", "f'(1)=ref", "f''(1)=ref", "f'''(1)=ref", "f^(4)(1)=ref"};
  PreparedRational q = prepare_rational(g);
  EXPECT_EQ(q.problem.target.variable(), "c");
  EXPECT_EQ(solve_prepared(q).runs[0].summary.results[0].formula, "0.04 + 0.96 * (1 - c)^5");
  g.target = "c";
  EXPECT_THROW((void)prepare_rational(g), Error);
}

}  // namespace
}  // namespace shaderfit::rational
