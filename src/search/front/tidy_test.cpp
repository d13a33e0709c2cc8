// The tidy step: noise constants removed or snapped on exact data, fitted constants kept on
// inexact data, the front recomputed and ended at its first member at noise level, and
// (acceptance of issues 17 and 27) exact physics formulas found by a search printed with no
// constant fitted to rounding noise and no `* 1`.
#include "search/front/tidy.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>
#include <regex>

#include "search/run/drawn_problem_test_util.hpp"
#include "search/run/seed_problem_test_util.hpp"
#include "search/search_context.hpp"
#include "shaderfit/core/random.hpp"
#include "shaderfit/cost/cost_model.hpp"
#include "shaderfit/eval/metrics.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/expr/print.hpp"
#include "shaderfit/search/front/front_table.hpp"

namespace shaderfit::search_detail {
namespace {

constexpr double kPi = std::numbers::pi;

// Inputs uniform in [lo, hi], the target computed exactly by `f` (float64).
SearchProblem exact_problem(std::vector<std::string> names, double lo, double hi,
                            const std::function<double(const std::vector<double>&)>& f) {
  const std::vector<std::pair<double, double>> ranges(names.size(), {lo, hi});
  return test::drawn_problem(std::move(names), ranges, f, 11, 500);
}

// Feynman-like data: each input in its own range (test::drawn_problem, seed 27, 500 rows).
SearchProblem feynman_problem(std::vector<std::string> names,
                              const std::vector<std::pair<double, double>>& ranges,
                              const std::function<double(const std::vector<double>&)>& f,
                              int digits = 0) {
  return test::drawn_problem(std::move(names), ranges, f, 27, 500, digits);
}

double coulomb_field(const std::vector<double>& v) {  // q1 r / (4 pi epsilon r^3)
  return v[0] * v[2] / (4 * kPi * v[1] * v[2] * v[2] * v[2]);
}
double distance(const std::vector<double>& v) {  // sqrt((x2 - x1)^2 + (y2 - y1)^2)
  return std::sqrt((v[1] - v[0]) * (v[1] - v[0]) + (v[3] - v[2]) * (v[3] - v[2]));
}
double relativistic_mass(const std::vector<double>& v) {  // m_0 / sqrt(1 - v^2 / c^2)
  return v[0] / std::sqrt(1 - v[1] * v[1] / (v[2] * v[2]));
}
SearchProblem coulomb_problem(int digits = 0) {
  return feynman_problem({"q1", "epsilon", "r"}, {{1, 5}, {1, 5}, {1, 5}}, coulomb_field, digits);
}
SearchProblem distance_problem(int digits = 0) {
  return feynman_problem({"x1", "x2", "y1", "y2"}, {{1, 5}, {1, 5}, {1, 5}, {1, 5}}, distance,
                         digits);
}
SearchProblem mass_problem(int digits = 0) {
  return feynman_problem({"m_0", "v", "c"}, {{1, 5}, {1, 2}, {3, 10}}, relativistic_mass, digits);
}

// The coefficients c minimising sum_i (rhs_i - sum_k c_k columns_k[i])^2 (normal equations,
// Gaussian elimination; the columns are few and well conditioned).
std::vector<double> least_squares(const std::vector<std::vector<double>>& columns,
                                  const std::vector<double>& rhs) {
  const std::size_t n = columns.size();
  std::vector<std::vector<long double>> a(n, std::vector<long double>(n + 1, 0));
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j < n; ++j)
      for (std::size_t r = 0; r < rhs.size(); ++r)
        a[i][j] += static_cast<long double>(columns[i][r]) * columns[j][r];
    for (std::size_t r = 0; r < rhs.size(); ++r)
      a[i][n] += static_cast<long double>(columns[i][r]) * rhs[r];
  }
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t k = i + 1; k < n; ++k) {
      const long double f = a[k][i] / a[i][i];
      for (std::size_t j = i; j <= n; ++j) a[k][j] -= f * a[i][j];
    }
  std::vector<double> c(n);
  for (std::size_t i = n; i-- > 0;) {
    long double v = a[i][n];
    for (std::size_t j = i + 1; j < n; ++j) v -= a[i][j] * c[j];
    c[i] = static_cast<double>(v / a[i][i]);
  }
  return c;
}

// `value` as the shortest text that reads back to it.
std::string exact(double value) { return format_number(value); }

// Whether a formula's text shows a neutral part: x * 1, 1 * x, x / 1, x + 0, 0 + x, x - 0, x^1.
bool shows_neutral_part(const std::string& formula) {
  static const std::regex neutral(
      R"([*/] -?1(?![0-9.e])|(^|[(, ])-?1 \*|[+-] 0(?![0-9.e])|(^|[(, ])-?0 [+-]|\^1(?![0-9]))");
  return std::regex_search(formula, neutral);
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
  EXPECT_EQ(nearest_simple_value(0.33), 1.0 / 3);
  EXPECT_EQ(nearest_simple_value(0.3), 1 / kPi);
  EXPECT_EQ(nearest_simple_value(-2.74), -2.75);
  EXPECT_EQ(nearest_simple_value(0.69), std::numbers::ln2);
  EXPECT_EQ(nearest_simple_value(1e6), 32.0);
  // The doubles nearest 1 / ln 2 (exp written with exp2), -1 / (2 ln 2), 1 / sqrt(2 pi), 8 pi
  // and 1 / (8 pi).
  EXPECT_EQ(nearest_simple_value(1.44269504089), std::numbers::log2e);
  EXPECT_EQ(nearest_simple_value(-0.72134752044), -0.7213475204444817);
  EXPECT_EQ(nearest_simple_value(0.39894228040), 0.3989422804014327);
  EXPECT_EQ(nearest_simple_value(25.132741228), 25.132741228718345);
  EXPECT_EQ(nearest_simple_value(0.03978873577), 0.039788735772973836);
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

TEST(Tidy, NoiseLevelIsRelativeToTheTargetsRms) {
  SearchProblem p;
  p.input_names = {"x"};
  p.inputs = {{1, 2, 3, 4}};
  p.target = {3, -3, 3, -3};
  EXPECT_DOUBLE_EQ(noise_level_rmse(p), kNoiseLevel * 3);
  p.weights = {1, 0, 0, 0};
  p.target = {2, -100, 100, 100};
  EXPECT_DOUBLE_EQ(noise_level_rmse(p), kNoiseLevel * 2);
}

// The forms the issue saw on the AI-Feynman fronts (exact data), each literally, with the
// constant its display showed as 12.566371 at full precision (that display is float32's).
TEST(Tidy, NoiseFormsOfExactFitsPrintExactly) {
  struct Case {
    SearchProblem problem;
    const char* noisy;
    const char* clean;    // the tidied formula
    const char* display;  // its text for people
  };
  const std::vector<Case> cases = {
      {coulomb_problem(),
       "q1 / ((r^2 + 5.110122e-10) * (epsilon * 12.566370614359172 + 4.879618e-09) - "
       "1.1723843e-08) - 2.4031165e-13",
       "q1 / (r^2 * (12.566370614359172 * epsilon))", "q1 / (r^2 * (12.566371 * epsilon))"},
      // As displayed (float32 constants): not at noise level until 12.566371 snaps to 4 pi.
      {coulomb_problem(),
       "q1 / ((r^2 + 5.110122e-10) * (epsilon * 12.566371 + 4.879618e-09) - 1.1723843e-08) - "
       "2.4031165e-13",
       "q1 / (r^2 * (12.566370614359172 * epsilon))", "q1 / (r^2 * (12.566371 * epsilon))"},
      {distance_problem(), "sqrt((x1 * 1.0000000000000004 - x2)^2 + ((y1 - y2)^2 - 7.7e-12))",
       "sqrt((x1 - x2)^2 + (y1 - y2)^2)", "sqrt((x1 - x2)^2 + (y1 - y2)^2)"},
      {distance_problem(), "(y2 * 1.6e-11 + 1) * sqrt((x1 - x2)^2 + (y1 - y2)^2) - 1.2e-11",
       "sqrt((x1 - x2)^2 + (y1 - y2)^2)", "sqrt((x1 - x2)^2 + (y1 - y2)^2)"},
      {mass_problem(),
       "(m_0 * 1.0000000000000004 + 3.1e-12) / sqrt(1 - (v / c)^2 - 2.2e-12) - 1.5e-12",
       "m_0 / sqrt(1 - (v / c)^2)", "m_0 / sqrt(1 - (v / c)^2)"},
  };
  ASSERT_TRUE(shows_neutral_part("sqrt((x1 * 1 - x2)^2 + (y1 - y2)^2)"));
  ASSERT_TRUE(shows_neutral_part("0 + x^1"));
  ASSERT_FALSE(shows_neutral_part("x * 1.5 + 10 - 0.5 * x^16 / 1e-3"));
  const SearchOptions o = test::seed_task_options();
  for (const Case& c : cases) {
    const std::vector<FrontMember> t = tidied(c.problem, {member(o, c.problem, c.noisy)});
    ASSERT_EQ(t.size(), 1u) << c.noisy;
    EXPECT_EQ(t[0].formula, c.clean) << c.noisy;
    EXPECT_EQ(to_infix(t[0].expression, PrintOptions::for_people()), c.display) << c.noisy;
    EXPECT_FALSE(shows_neutral_part(c.display));
    EXPECT_LE(t[0].metrics.rmse, noise_level_rmse(c.problem)) << c.noisy;
    EXPECT_LE(t[0].cost, member(o, c.problem, c.noisy).cost) << c.noisy;
  }
}

// Data with float64-level noise of its own (written with 10 significant digits) and noise terms
// fitted to that noise: each term lowers the loss a little, so dropping the terms raises it by
// more than 1e-9 of the member's loss plus the 1e-12 rounding floor (the rule for members that
// are not at noise level, which kept them); at noise level they go.
TEST(Tidy, CompensatingNoiseTermsAreRemovedAtNoiseLevel) {
  const SearchOptions o = test::seed_task_options();
  struct Case {
    SearchProblem problem;
    std::function<double(const std::vector<double>&)> f;
    // the noisy form with its constants a and b, and the two columns a and b multiply
    std::function<std::string(double, double)> noisy;
    std::function<std::pair<double, double>(const std::vector<double>&)> columns;
    const char* clean;
  };
  const std::vector<Case> cases = {
      {distance_problem(10), distance,
       [](double a, double b) {
         return "(y2 * " + exact(a) + " + 1) * sqrt((x1 - x2)^2 + (y1 - y2)^2) - " + exact(-b);
       },
       [](const std::vector<double>& v) {
         return std::pair{v[3] * distance(v), 1.0};
       },
       "sqrt((x1 - x2)^2 + (y1 - y2)^2)"},
      {mass_problem(10), relativistic_mass,
       [](double a, double b) {
         return "(m_0 + " + exact(a) + ") / sqrt(1 - (v / c)^2) + " + exact(b) + " * v";
       },
       [](const std::vector<double>& v) {
         return std::pair{1 / std::sqrt(1 - v[1] * v[1] / (v[2] * v[2])), v[1]};
       },
       "m_0 / sqrt(1 - (v / c)^2)"},
  };
  for (const Case& c : cases) {
    const SearchProblem& p = c.problem;
    std::vector<std::vector<double>> columns(2);
    std::vector<double> residual, row(p.inputs.size());
    for (std::size_t i = 0; i < p.target.size(); ++i) {
      for (std::size_t k = 0; k < row.size(); ++k) row[k] = p.inputs[k][i];
      const auto [ca, cb] = c.columns(row);
      columns[0].push_back(ca);
      columns[1].push_back(cb);
      residual.push_back(p.target[i] - c.f(row));
    }
    const std::vector<double> ab = least_squares(columns, residual);
    const std::string noisy = c.noisy(ab[0], ab[1]);
    const FrontMember m = member(o, p, noisy.c_str());
    const FrontMember clean = member(o, p, c.clean);
    // What the old rule allowed: the clean form is outside it, the noisy one at noise level.
    std::vector<double> y(p.target.begin(), p.target.end());
    for (double& v : y) v += kTidyRoundingNoise * std::abs(v);
    const double floor = loss_value(o.loss, error_metrics(y, p.target));
    ASSERT_GT(clean.loss, m.loss + kTidyRelativeLoss * m.loss + floor) << noisy;
    ASSERT_LE(m.metrics.rmse, noise_level_rmse(p)) << noisy;
    const std::vector<FrontMember> t = tidied(p, {m});
    ASSERT_EQ(t.size(), 1u);
    EXPECT_EQ(t[0].formula, c.clean) << noisy;
  }
}

// Fitted to an approximation (exp on [0, 1] by a least-squares cubic): far from noise level, so
// the constants near simple values (c0 near 1) stay as today's rule keeps them.
TEST(Tidy, ApproximationsKeepTheirConstants) {
  const SearchProblem p =
      feynman_problem({"x"}, {{0, 1}}, [](const std::vector<double>& v) { return std::exp(v[0]); });
  std::vector<std::vector<double>> columns(4);
  for (double x : p.inputs[0])
    for (int k = 0; k < 4; ++k) columns[static_cast<std::size_t>(k)].push_back(std::pow(x, k));
  const std::vector<double> c = least_squares(columns, p.target);
  const std::string formula = exact(c[0]) + " + x * (" + exact(c[1]) + " + x * (" + exact(c[2]) +
                              " + x * " + exact(c[3]) + "))";
  const SearchOptions o = test::seed_task_options();
  const FrontMember m = member(o, p, formula.c_str());
  ASSERT_GT(m.metrics.rmse, 1e3 * noise_level_rmse(p));
  ASSERT_LT(std::abs(c[0] - 1), 1e-3);
  const std::vector<FrontMember> t = tidied(p, {m});
  ASSERT_EQ(t.size(), 1u);
  EXPECT_EQ(t[0].formula, formula);
  EXPECT_EQ(t[0].expression, m.expression);
  EXPECT_EQ(t[0].loss, m.loss);
}

// A front ends at its first member at noise level: a costlier one that fits the data's own
// noise better (constants whose product alone matters, from a real front, refitted here) is not
// kept, though its loss is lower.
TEST(Tidy, FrontEndsAtItsFirstNoiseLevelMember) {
  const SearchProblem p = coulomb_problem(10);
  const SearchOptions o = test::seed_task_options();
  constexpr double k = 0.9991008370678403;
  std::vector<std::vector<double>> column(1);
  for (std::size_t i = 0; i < p.target.size(); ++i) {
    const double q1 = p.inputs[0][i], epsilon = p.inputs[1][i], r = p.inputs[2][i];
    column[0].push_back(q1 / -(epsilon * (r * r * k)));
  }
  const double c = least_squares(column, p.target)[0];
  const std::string costly = exact(c) + " * (q1 / -(epsilon * (r^2 * " + exact(k) + ")))";
  const std::vector<FrontMember> front = {
      member(o, p, "0.02"), member(o, p, "q1 / (r^2 * (12.566370614359172 * epsilon))"),
      member(o, p, costly.c_str())};
  ASSERT_LT(front[1].cost, front[2].cost);
  ASSERT_LT(front[2].loss, front[1].loss);
  ASSERT_LE(front[1].metrics.rmse, noise_level_rmse(p));
  const std::vector<FrontMember> t = tidied(p, front);
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t[0].formula, "0.02");
  EXPECT_EQ(t[1].formula, "q1 / (r^2 * (12.566370614359172 * epsilon))");
}

// A constant of the formula (a literal or a fitted parameter) that rounding noise would leave:
// tiny, or within 1e-7 of a simple value without being it.
bool noise_constant(double c) {
  const double s = nearest_simple_value(c);
  return c != s && std::abs(c - s) <= 1e-7 * std::max(1.0, std::abs(s));
}

// Issues 17 and 27's acceptance: exact physics formulas, searched (with a start formula whose
// constants the search refits, to rounding noise); the members that fit exactly print with no
// constant fitted to noise, no member's text shows `* 1` or the like, and the front ends at its
// first member at noise level.
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
    for (std::size_t i = 0; i < s.front.size(); ++i) {
      const FrontMember& m = s.front[i];
      std::printf("%s: cost %g loss %.3g  %s\n", c.name, m.cost, m.loss, m.formula.c_str());
      EXPECT_FALSE(shows_neutral_part(m.formula)) << m.formula;
      const std::string display = to_infix(m.expression, PrintOptions::for_people());
      EXPECT_FALSE(shows_neutral_part(display)) << display;
      // The front ends at its first member at noise level.
      if (m.metrics.rmse <= noise_level_rmse(p)) {
        EXPECT_EQ(i + 1, s.front.size()) << m.formula;
      }
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

namespace shaderfit::search_detail {
namespace {

// A clamp that never acts on the rows goes (it would cut the function on a wider domain); one
// that acts stays.
TEST(Tidy, ClampsThatNeverActAreDropped) {
  const SearchOptions o = test::seed_task_options();
  const SearchProblem p = coulomb_problem();
  const struct {
    const char* given;
    const char* tidy;
  } cases[] = {
      {"saturate(q1 / (r^2 * (epsilon * 12.566370614359172)))",
       "q1 / (r^2 * (12.566370614359172 * epsilon))"},
      {"min(q1 / (r^2 * (epsilon * 12.566370614359172)), 1e6)",
       "q1 / (r^2 * (12.566370614359172 * epsilon))"},
      {"abs(q1) / (r^2 * (epsilon * 12.566370614359172))",
       "q1 / (r^2 * (12.566370614359172 * epsilon))"},
      {"abs(-q1) / (r^2 * (epsilon * 12.566370614359172))",
       "q1 / (r^2 * (12.566370614359172 * epsilon))"},
  };
  for (const auto& c : cases) {
    const std::vector<FrontMember> t = tidied(p, {member(o, p, c.given)});
    ASSERT_EQ(t.size(), 1u) << c.given;
    EXPECT_EQ(t[0].formula, c.tidy) << c.given;
  }
  // On data clamped at 0.5 the clamp acts: kept.
  const SearchProblem clamped = feynman_problem(
      {"x"}, {{0, 1}}, [](const std::vector<double>& v) { return std::min(v[0], 0.5); });
  const std::vector<FrontMember> kept = tidied(clamped, {member(o, clamped, "min(x, 0.5)")});
  ASSERT_EQ(kept.size(), 1u);
  EXPECT_EQ(kept[0].formula, "min(x, 0.5)");
  // A clamp that acts where a zero factor hides it from the result is no idle clamp (fuzz4's
  // height blend): max(x - 0.5, 0) / (max(x - 0.5, 0) + y) without its second max is 0 / 0 on
  // the line x + y = 0.5.
  const SearchProblem masked = feynman_problem({"x", "y"}, {{0, 1}, {0.25, 1}},
                                               [](const std::vector<double>& v) {
                                                 const double a = std::max(v[0] - 0.5, 0.0);
                                                 return a / (a + v[1]);
                                               });
  const std::vector<FrontMember> blend =
      tidied(masked, {member(o, masked, "max(x - 0.5, 0) / (max(x - 0.5, 0) + y)")});
  ASSERT_EQ(blend.size(), 1u);
  EXPECT_EQ(blend[0].formula, "max(x - 0.5, 0) / (max(x - 0.5, 0) + y)");
}

// Issue 42: no two members shown differ by less than the minimum step; small steps show once
// they add up to it; the others are kept, marked, and left out of the table.
TEST(MinorSteps, AMemberIsShownWhereItLowersTheLossByTheMargin) {
  std::vector<FrontMember> f;
  for (double loss : {1.0, 0.5, 0.499, 0.496, 0.494, 0.2, 0.2}) {
    FrontMember m;
    m.cost = static_cast<double>(f.size());
    m.loss = m.metrics.mse = loss;
    m.expression = parse_formula("x", {.variables = {"x"}});
    f.push_back(m);
  }
  mark_minor_steps(f, 0.01);
  std::vector<bool> minor;
  for (const FrontMember& m : f) minor.push_back(m.minor_step);
  EXPECT_EQ(minor, (std::vector<bool>{false, false, true, true, false, false, true}));
  SearchSummary s;
  s.front = f;
  const std::string table = front_table(s);
  EXPECT_NE(table.find("3 costlier members not shown"), std::string::npos) << table;
  EXPECT_EQ(table.find("0.499"), std::string::npos) << table;
  mark_minor_steps(f, 0);
  minor.clear();
  for (const FrontMember& m : f) minor.push_back(m.minor_step);
  EXPECT_EQ(minor, (std::vector<bool>{false, false, false, false, false, false, true}));
  // Kept in the JSON, marked, and read back.
  FrontMember m = f.back();
  const nlohmann::json j = front_member_json(m, FrontJson::Exact);
  EXPECT_EQ(j.at("minor_step"), true);
  EXPECT_FALSE(front_member_json(f.front(), FrontJson::Result).contains("minor_step"));
}

}  // namespace
}  // namespace shaderfit::search_detail

namespace shaderfit::search_detail {
namespace {

// What the JSON's text reads back to is what the front counts: -(1.27 - |x|) is printed
// |x| - 1.27, one instruction fewer; the member takes that form and cost, and a member it now
// dominates leaves the front.
TEST(CountAsPrinted, AMemberWhoseTextReadsBackCheaperTakesThatCost) {
  const SearchProblem p = exact_problem({"x"}, -1, 1, [](const std::vector<double>& v) {
    return 1.5 + 1.28 * (std::abs(v[0]) - 1.27);
  });
  const SearchOptions o = test::seed_task_options();
  const auto at = [&](const char* formula) {
    FrontMember m;
    m.expression = parse_formula(formula, {.variables = {"x"}});
    m.metrics = SearchContext(o, p).score(m.expression);
    m.loss = loss_value(o.loss, m.metrics);
    m.cost = expression_cost(m.expression, o.cost);
    m.formula = to_infix(m.expression);
    return m;
  };
  FrontMember worse = at("1.5 + 1.28 * (abs(x) - 1.2)");
  FrontMember signed_group = at("1.5 + 1.28 * -(1.27 - abs(x))");
  ASSERT_EQ(signed_group.cost, worse.cost + 1);
  std::vector<FrontMember> front = {worse, signed_group};
  count_as_printed(front, o);
  ASSERT_EQ(front.size(), 1u);
  EXPECT_EQ(front[0].cost, worse.cost);
  EXPECT_EQ(front[0].formula, "1.5 + 1.28 * (abs(x) - 1.27)");
  EXPECT_EQ(front[0].loss, signed_group.loss);
}

}  // namespace
}  // namespace shaderfit::search_detail
