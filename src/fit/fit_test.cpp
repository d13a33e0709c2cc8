#include "shaderfit/fit/fit.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "shaderfit/core/error.hpp"
#include "shaderfit/core/random.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/fit/linear.hpp"

namespace shaderfit {
namespace {

Expression parse(const char* text, std::vector<std::string> params, std::vector<double> values) {
  ParseOptions po;
  po.variables = {"r0", "x"};
  po.parameters = std::move(params);
  po.parameter_values = std::move(values);
  return parse_formula(text, po);
}

struct Data {
  std::vector<double> r0, x, y;
};

Data make_data(std::size_t rows, double (*f)(double, double)) {
  Rng rng(3);
  Data d;
  for (std::size_t i = 0; i < rows; ++i) {
    d.r0.push_back(uniform(rng, 0.02, 0.9));
    d.x.push_back(uniform(rng, 0.0, 1.0));
    d.y.push_back(f(d.r0.back(), d.x.back()));
  }
  return d;
}

TEST(LinearScaling, ClosedForm) {
  const std::vector<double> f = {0, 1, 2, 3}, y = {1, 3, 5, 7};
  const LinearScaling s = fit_linear_scaling(f, y);
  EXPECT_NEAR(s.a, 2.0, 1e-15);
  EXPECT_NEAR(s.b, 1.0, 1e-15);
  EXPECT_NEAR(s.mse, 0.0, 1e-28);
  const LinearScaling flat = fit_linear_scaling(std::vector<double>{2, 2, 2, 2}, y);
  EXPECT_EQ(flat.a, 0.0);
  EXPECT_NEAR(flat.b, 4.0, 1e-15);
  // Weights: the zero-weight row does not count.
  const LinearScaling w =
      fit_linear_scaling(std::vector<double>{0, 1, 2, 3}, std::vector<double>{1, 3, 5, 100},
                         std::vector<double>{1, 1, 1, 0});
  EXPECT_NEAR(w.a, 2.0, 1e-12);
}

TEST(LinearLeastSquares, SolvesAndToleratesRankDeficiency) {
  const std::vector<double> a = {1, 2, 3, 4}, b = {1, 1, 1, 1}, y = {3, 5, 7, 9};
  const double* cols[] = {a.data(), b.data(), a.data()};
  const auto c = solve_least_squares(std::span<const double* const>(cols, 2), y);
  EXPECT_NEAR(c[0], 2.0, 1e-12);
  EXPECT_NEAR(c[1], 1.0, 1e-12);
  const auto d = solve_least_squares(cols, y);  // a twice: a least-squares solution still fits
  EXPECT_NEAR(d[0] + d[2], 2.0, 1e-9);
}

// The best line to x^2 on [0, 1] is x - 1/8 (error +-1/8 at 0, 1/2 and 1); Lawson's iteration
// approaches it linearly, so within 0.5% after its default 60 solves.
TEST(LinearMinimax, NearTheBestLineAndWeighs) {
  std::vector<double> x, one, y;
  for (int i = 0; i <= 1000; ++i) {
    x.push_back(i / 1000.0);
    one.push_back(1);
    y.push_back(x.back() * x.back());
  }
  const double* cols[] = {one.data(), x.data()};
  const auto worst = [&](const std::vector<double>& c, double upto) {
    double e = 0;
    for (std::size_t i = 0; i < x.size(); ++i)
      if (x[i] <= upto) e = std::max(e, std::abs(c[0] + c[1] * x[i] - y[i]));
    return e;
  };
  const auto c = solve_minimax_linear(cols, y);
  EXPECT_NEAR(c[1], 1.0, 1e-3);
  EXPECT_LT(worst(c, 1), 0.125 * 1.005);
  EXPECT_LT(worst(solve_minimax_linear(cols, y, {}, 400), 1), 0.125 * 1.0001);
  // Least squares (-1/6, 1) is worse: the minimax is not just the first solve.
  EXPECT_GT(worst(solve_least_squares(cols, y), 1), 0.16);
  // Zero weight on the rows above 1/2: the best line on [0, 1/2], x / 2 - 1/32.
  std::vector<double> w(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) w[i] = x[i] <= 0.5 ? 1 : 0;
  const auto h = solve_minimax_linear(cols, y, w);
  EXPECT_NEAR(h[1], 0.5, 1e-3);
  EXPECT_LT(worst(h, 0.5), 1.0 / 32 * 1.005);
}

TEST(Fit, LinearInParametersDetection) {
  EXPECT_TRUE(is_linear_in_parameters(parse("a * x + b", {"a", "b"}, {})));
  EXPECT_TRUE(is_linear_in_parameters(parse("r0 + (x - r0 * a) * x^4 / 2 - b", {"a", "b"}, {})));
  EXPECT_FALSE(is_linear_in_parameters(parse("a * b * x", {"a", "b"}, {})));
  EXPECT_FALSE(is_linear_in_parameters(parse("pow(x, a)", {"a"}, {})));
  EXPECT_FALSE(is_linear_in_parameters(parse("x / a", {"a"}, {})));
  EXPECT_TRUE(is_linear_in_parameters(parse("x^2", {}, {})));
}

TEST(Fit, JacobianMatchesFiniteDifferences) {
  const char* formulas[] = {"a * x + b",
                            "pow(x + 0.1, a) * b",
                            "exp2(a * x) / (b + r0)",
                            "sqrt(a + x) * rsqrt(b + r0)",
                            "log(a + x) + log2(b + x) + exp(a * r0)",
                            "rcp(a + x) + sin(a * x) * cos(b * r0)",
                            "min(a * x, b) + max(a, b * r0) + abs(a - x) + (a * x)^3",
                            "fma(a, x, b * r0) - -a"};
  const Data d = make_data(100, [](double r0, double x) { return r0 + x; });
  const double* cols[] = {d.r0.data(), d.x.data()};
  for (const char* text : formulas) {
    Expression e = parse(text, {"a", "b"}, {0.7, 1.3});
    std::vector<double> v(100), j(200), vp(100), jp(200);
    evaluate_with_jacobian(e, cols, 100, v, j);
    for (std::size_t p = 0; p < 2; ++p) {
      Expression ep = e;
      const double h = 1e-6;
      ep.parameter_values[p] += h;
      evaluate_with_jacobian(ep, cols, 100, vp, jp);
      for (std::size_t i = 0; i < 100; ++i)
        EXPECT_NEAR(j[p * 100 + i], (vp[i] - v[i]) / h, 1e-4 * (1 + std::abs(j[p * 100 + i])))
            << text << " p" << p;
    }
  }
}

TEST(Fit, LinearFormulasAreSolvedDirectly) {
  const Data d = make_data(
      500, [](double r0, double x) { return r0 + (0.965 * x - r0) * x * x * x * x + 0.01; });
  Expression e = parse("r0 + (a * x - r0) * x^4 + b", {"a", "b"}, {1.0, 0.0});
  FitProblem p{&e, {d.r0.data(), d.x.data()}, d.y};
  FitSummary s;
  fit_parameters(FitOptions{}, p, &s);
  EXPECT_TRUE(s.linear);
  EXPECT_NEAR(s.parameters[0], 0.965, 1e-10);
  EXPECT_NEAR(s.parameters[1], 0.01, 1e-10);
  EXPECT_LT(s.final_cost, 1e-25);
}

TEST(Fit, LevenbergMarquardtRecoversAnExponent) {
  const Data d =
      make_data(500, [](double r0, double x) { return r0 + (1 - r0) * std::pow(x, 4.6) * 0.97; });
  Expression e = parse("r0 + (1 - r0) * pow(x, a) * b", {"a", "b"}, {3.0, 1.0});
  FitProblem p{&e, {d.r0.data(), d.x.data()}, d.y};
  FitSummary s;
  fit_parameters(FitOptions{}, p, &s);
  EXPECT_FALSE(s.linear);
  EXPECT_NEAR(s.parameters[0], 4.6, 1e-6);
  EXPECT_NEAR(s.parameters[1], 0.97, 1e-6);
  EXPECT_LT(s.final_cost, s.initial_cost);
  EXPECT_FALSE(s.brief_report().empty());
}

TEST(Fit, BadProblems) {
  FitSummary s;
  FitOptions bad;
  bad.max_iterations = 0;
  std::string why;
  EXPECT_FALSE(bad.is_valid(&why));
  Expression e = parse("a * x", {"a"}, {1.0});
  const std::vector<double> y = {1.0};
  EXPECT_THROW(fit_parameters(bad, {&e, {nullptr, nullptr}, y}, &s), Error);
  EXPECT_THROW(fit_parameters(FitOptions{}, {&e, {nullptr}, y}, &s), Error);
  EXPECT_THROW(fit_parameters(FitOptions{}, {nullptr, {}, y}, &s), Error);
}

}  // namespace
}  // namespace shaderfit
