// fit_parameters with FitOptions::minimax: Lawson's reweighting against known minimax optima.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "shaderfit/core/error.hpp"
#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/fit/fit.hpp"

namespace shaderfit {
namespace {

struct Samples {
  std::vector<double> x, y;
};

Samples sample(double (*f)(double), double lo, double hi, std::size_t n) {
  Samples s;
  for (std::size_t i = 0; i < n; ++i) {
    s.x.push_back(lo + (hi - lo) * static_cast<double>(i) / static_cast<double>(n - 1));
    s.y.push_back(f(s.x.back()));
  }
  return s;
}

Expression over_x(const char* text, std::vector<std::string> params) {
  ParseOptions po;
  po.variables = {"x"};
  po.parameter_values.assign(params.size(), 0.0);
  po.parameters = std::move(params);
  return parse_formula(text, po);
}

FitSummary minimax_fit(Expression* e, const Samples& s, bool linear_solver = true) {
  FitOptions o;
  o.minimax = true;
  o.use_linear_solver = linear_solver;
  FitSummary r;
  fit_parameters(o, {e, {s.x.data()}, s.y}, &r);
  e->parameter_values = r.parameters;
  return r;
}

double error_at(const Expression& e, double (*f)(double), double x) {
  const double col[] = {x};
  const double* cols[] = {col};
  double v = 0;
  evaluate(e, cols, std::span<double>(&v, 1));
  return v - f(x);
}

double exp_of(double x) { return std::exp(x); }
double exp2_of(double x) { return std::exp2(x); }

// The best straight line for exp on [0, 1]: b = e - 1, and the error equioscillates at 0,
// ln(e - 1) and 1 with magnitude (2 - e + (e - 1) ln(e - 1)) / 2.
TEST(Minimax, StraightLineForExpEquioscillates) {
  const double e1 = std::numbers::e - 1, xm = std::log(e1);
  const double optimum = (2 - std::numbers::e + e1 * std::log(e1)) / 2;
  const Samples s = sample(exp_of, 0, 1, 2001);
  for (bool linear_solver : {true, false}) {
    Expression line = over_x("a + b * x", {"a", "b"});
    const FitSummary r = minimax_fit(&line, s, linear_solver);
    EXPECT_EQ(r.linear, linear_solver);
    EXPECT_GT(r.minimax_passes, 0);
    EXPECT_NEAR(r.final_cost, optimum, 0.01 * optimum);
    EXPECT_NEAR(line.parameter_values[1], e1, 0.01 * e1);
    // Alternating signs at the three points, equal magnitudes within 1%.
    const double at0 = error_at(line, exp_of, 0);
    const double inner = error_at(line, exp_of, std::log(line.parameter_values[1]));
    const double at1 = error_at(line, exp_of, 1);
    EXPECT_LT(at0 * inner, 0);
    EXPECT_LT(inner * at1, 0);
    for (double v : {at0, inner, at1}) EXPECT_NEAR(std::abs(v), optimum, 0.01 * optimum);
    EXPECT_NEAR(std::log(line.parameter_values[1]), xm, 0.01);
  }
}

// The degree-3 polynomial for exp2 on [0, 1] against Sollya's remez (docs/rational.md,
// "Against Sollya": 1.0703434949490895e-4), by the linear and by the LM passes.
TEST(Minimax, CubicForExp2MatchesSollya) {
  const double sollya = 1.0703434949490895e-4;
  const Samples s = sample(exp2_of, 0, 1, 2001);
  for (bool linear_solver : {true, false}) {
    Expression cubic = over_x("a + x * (b + x * (c + x * d))", {"a", "b", "c", "d"});
    const FitSummary r = minimax_fit(&cubic, s, linear_solver);
    EXPECT_NEAR(r.final_cost, sollya, 0.01 * sollya) << linear_solver;
    // Least squares errs by more at the worst row.
    FitSummary ls;
    Expression lsq = over_x("a + x * (b + x * (c + x * d))", {"a", "b", "c", "d"});
    fit_parameters(FitOptions{}, {&lsq, {s.x.data()}, s.y}, &ls);
    lsq.parameter_values = ls.parameters;
    double worst = 0;
    for (double x : s.x) worst = std::max(worst, std::abs(error_at(lsq, exp2_of, x)));
    EXPECT_GT(worst, 1.1 * r.final_cost);
  }
}

// Weights scale each row's error (max w |r|); weight 0 drops a row; never worse than the start.
TEST(Minimax, WeightsAndStart) {
  const Samples s = sample(exp_of, 0, 1, 201);
  std::vector<double> w(s.x.size(), 1.0);
  for (std::size_t i = 150; i < w.size(); ++i) w[i] = 0;
  Expression line = over_x("a + b * x", {"a", "b"});
  FitOptions o;
  o.minimax = true;
  FitSummary r;
  fit_parameters(o, {&line, {s.x.data()}, s.y, w}, &r);
  const Samples part = sample(exp_of, 0, s.x[149], 150);
  Expression direct = over_x("a + b * x", {"a", "b"});
  const FitSummary d = minimax_fit(&direct, part);
  EXPECT_NEAR(r.final_cost, d.final_cost, 1e-3 * d.final_cost);
  // From the optimum, one pass cannot do better: the start is kept.
  Expression at = over_x("a + b * x", {"a", "b"});
  at.parameter_values = r.parameters;
  o.minimax_iterations = 1;
  FitSummary again;
  fit_parameters(o, {&at, {s.x.data()}, s.y, w}, &again);
  EXPECT_LE(again.final_cost, again.initial_cost);
  EXPECT_NE(again.brief_report().find("Lawson"), std::string::npos);
  o.minimax_iterations = 0;
  std::string why;
  EXPECT_FALSE(o.is_valid(&why));
  EXPECT_THROW(fit_parameters(o, {&at, {s.x.data()}, s.y}, &again), Error);
}

}  // namespace
}  // namespace shaderfit
